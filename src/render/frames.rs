//! The frame of every textured cell (paper section 6): the site's long-axis direction and
//! semi-axes, in which a texture tile spans one cell and its lines run along the field; and,
//! for hatching with a flat angle, the frames of cells without a direction (round ones, where
//! paper Figure 6 fades the texture), turned to that angle and given spacings on a ladder of
//! whole octaves, so that flat neighbours of about one size share a spacing and their lines
//! run on from cell to cell. Geometry is `f64` in domain units.

use crate::field::Tensor;

/// A site's frame: long-axis direction and semi-axes, precomputed once per render.
#[derive(Clone, Copy)]
pub(super) struct Frame {
    pub(super) angle: f64,
    pub(super) cos: f64,
    pub(super) sin: f64,
    pub(super) a: f64,
    pub(super) b: f64,
    pub(super) anisotropy: f32,
}

impl Frame {
    /// The frame of a site with metric `m`.
    pub(super) fn of(m: &Tensor) -> Self {
        let e = m.eigen();
        let (a, b) = (e.l1.abs().max(1e-9), e.l2.abs().max(1e-9));
        Frame {
            angle: e.angle,
            cos: e.angle.cos(),
            sin: e.angle.sin(),
            a,
            b,
            anisotropy: e.anisotropy() as f32,
        }
    }
}

/// How cells without a direction are hatched.
#[derive(Clone, Copy, Debug)]
pub(super) struct FlatHatching {
    /// The lines' direction, radians from +x.
    pub(super) angle: f64,
    /// Cells less anisotropic than this count as flat.
    pub(super) below: f32,
    /// The largest short axis a flat cell's spacing is made from (domain units).
    pub(super) largest: f64,
}

/// Every cell's frame. With `flat`, cells rounder than `flat.below` are turned to its angle and
/// counted as fully anisotropic (no fade); their short axes (at most `flat.largest`) go on a
/// ladder of whole octaves, and those within half an octave of the flat cells' median
/// ([`median_octave`]) all take the median's rung.
pub(super) fn cell_frames(metrics: &[Tensor], flat: Option<FlatHatching>) -> Vec<Frame> {
    let mut frames: Vec<Frame> = metrics.iter().map(Frame::of).collect();
    let Some(flat) = flat else {
        return frames;
    };
    let is_flat = |f: &Frame| f.anisotropy < flat.below;
    let octaves = |f: &Frame| f.b.min(flat.largest).max(1e-9).log2();
    let median = median_octave(frames.iter().filter(|f| is_flat(f)).map(octaves).collect());
    let (sin, cos) = flat.angle.sin_cos();
    for f in frames.iter_mut().filter(|f| is_flat(f)) {
        let o = octaves(f);
        let rung = if (o - median).abs() < 0.5 {
            median.round()
        } else {
            o.round()
        };
        let b = 2f64.powf(rung);
        *f = Frame {
            angle: flat.angle,
            cos,
            sin,
            a: f.a.max(b),
            b,
            anisotropy: 1.0,
        };
    }
    frames
}

/// The median of the flat cells' sizes `octaves` (log₂ of their short axes; 0 for none). The
/// ladder's rungs change at half octaves, which cut through the sizes of a flat area wherever
/// they spread across one (a grey wall whose cells are 5.5 to 6.5 px straddles 2^2.5 = 5.66
/// px), and its cells, hatched at 4 and 8 px by turns, read as patches; every cell within half
/// an octave of the median takes the median's rung, so a flat area shares one. Cells farther
/// from it (a galaxy's in a black sky) keep their own rung.
fn median_octave(mut octaves: Vec<f64>) -> f64 {
    if octaves.is_empty() {
        return 0.0;
    }
    let middle = octaves.len() / 2;
    *octaves.select_nth_unstable_by(middle, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_area_is_hatched_at_one_spacing() {
        // Round cells of a grey wall, 5.5 to 6.5 units across their short axis: rounded to
        // whole octaves they straddle 2^2.5 = 5.66 and split between spacings 4 and 8
        // (patches); within half an octave of their median, they share its rung. Two cells
        // about half their size (a detail in the wall) keep their own, finer one.
        let mut metrics: Vec<Tensor> = (0..41)
            .map(|i| Tensor::isotropic(5.5 + f64::from(i) / 40.0))
            .collect();
        metrics.extend([Tensor::isotropic(3.0), Tensor::isotropic(3.2)]);
        let angle = (-45f64).to_radians();
        let flat = FlatHatching {
            angle,
            below: 0.25,
            largest: 100.0,
        };
        let frames = cell_frames(&metrics, Some(flat));
        let wall: Vec<f64> = frames[..41].iter().map(|f| f.b).collect();
        assert!(wall.iter().all(|&b| b == wall[0]), "spacings {wall:?}");
        assert_eq!(wall[0], 8.0, "the median's whole octave");
        assert!(frames[41..].iter().all(|f| f.b == 4.0), "the detail's rung");
        assert!(frames.iter().all(|f| f.angle == angle));
    }

    #[test]
    fn without_a_flat_angle_every_cell_keeps_its_own_frame() {
        let metrics = [Tensor::isotropic(5.5), Tensor::from_eigen(0.3, 6.0, 2.0)];
        let frames = cell_frames(&metrics, None);
        assert_eq!(frames[0].b, 5.5);
        assert_eq!((frames[1].a, frames[1].b), (6.0, 2.0));
        assert!((frames[1].angle - 0.3).abs() < 1e-12);
    }
}
