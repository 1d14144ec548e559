//! The frame of every textured cell (paper section 6): the site's long-axis direction and
//! semi-axes, in which a texture tile spans one cell and its lines run along the field; and,
//! for hatching with a flat angle, the frames of cells without a direction (round ones, where
//! paper Figure 6 fades the texture, ones whose direction their neighbours do not share, the
//! grain of a plain, and ones with no structure of their own), turned to that angle and given
//! spacings on a ladder of whole octaves, one rung per flat area (touching flat cells of
//! gradually changing size), so that a plain is hatched at one spacing and its lines run on
//! from cell to cell; the cells with a direction are put on the same ladder, their angles
//! rounded to 15° steps from the flat angle (the weakly directed ones first turned part of
//! the way to it) and their short axes to whole octaves, so that neighbours along a form
//! share one family of lines. Geometry is `f64` in domain units.

use crate::field::Tensor;
use crate::render::support::disjoint::DisjointSets;

/// A site's frame: long-axis direction and semi-axes, precomputed once per render.
#[derive(Clone, Copy)]
pub(crate) struct Frame {
    pub(crate) angle: f64,
    pub(crate) cos: f64,
    pub(crate) sin: f64,
    pub(crate) a: f64,
    pub(crate) b: f64,
    pub(crate) anisotropy: f32,
}

impl Frame {
    /// The frame of a site with metric `m`.
    pub(crate) fn of(m: &Tensor) -> Self {
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

    /// The frame of a site with metric `m` counted as having no direction.
    pub(crate) fn undirected(m: &Tensor) -> Self {
        Frame {
            anisotropy: 0.0,
            ..Frame::of(m)
        }
    }
}

/// How cells without a direction are hatched.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FlatHatching {
    /// The lines' direction, radians from +x.
    pub(crate) angle: f64,
    /// Cells less anisotropic than this count as flat.
    pub(crate) below: f32,
    /// The largest short axis a flat cell's spacing is made from (domain units).
    pub(crate) largest: f64,
}

/// Every cell's frame. With `flat`, cells rounder than `flat.below`, or whose direction their
/// neighbourhood does not bear out ([`directed_anisotropy`] under `flat.below`), are turned to
/// its angle and counted as fully anisotropic (no fade), and hatched at a spacing from a ladder
/// of whole octaves of their short axes (at most `flat.largest`), one rung per flat area
/// ([`flat_areas`]): `neighbours` are the pairs of cells that touch, each once. The other
/// cells keep their direction (turned part of the way to the flat angle where their
/// neighbourhood bears it out only a little), rounded with their size onto the ladder
/// ([`on_the_ladder`]).
/// Cells `quiet` marks (no structure of their own, `quiet_cells.rs`) count as round, their
/// axes kept (a round cell of the same area would hatch a brick face or a plain in spacings
/// twice as coarse).
pub(crate) fn cell_frames(
    metrics: &[Tensor],
    neighbours: &[[u32; 2]],
    flat: Option<FlatHatching>,
    quiet: Option<&[bool]>,
) -> Vec<Frame> {
    let Some(flat) = flat else {
        return metrics.iter().map(Frame::of).collect();
    };
    let mut frames: Vec<Frame> = metrics
        .iter()
        .enumerate()
        .map(|(i, m)| match quiet {
            Some(q) if q.get(i) == Some(&true) => Frame::undirected(m),
            _ => Frame::of(m),
        })
        .collect();
    let directed = directed_anisotropy(&frames, neighbours);
    let octaves: Vec<Option<f64>> = frames
        .iter()
        .zip(&directed)
        .map(|(f, &d)| {
            (f.anisotropy < flat.below || d < flat.below)
                .then(|| f.b.min(flat.largest).max(1e-9).log2())
        })
        .collect();
    let rungs = flat_areas(&octaves, neighbours, quiet);
    let (sin, cos) = flat.angle.sin_cos();
    for ((f, rung), &d) in frames.iter_mut().zip(rungs).zip(&directed) {
        let Some(rung) = rung else {
            let weight = f64::from((d - flat.below) / BLEND).clamp(0.0, 1.0);
            *f = on_the_ladder(*f, &flat, weight);
            continue;
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

/// A directed cell's frame with its angle rounded to [`ANGLE_STEP`] from the flat angle and
/// its short axis, at most `flat.largest`, to the nearest whole octave (as the flat cells'
/// rungs), so that directed cells beside
/// each other that differ a little in direction or size hatch in one family of lines running on
/// from cell to cell, and those near the flat angle in the flat areas' own lines (each cell at
/// its own angle and at a quarter of its own width, no two neighbours' lines would meet: a form
/// would be a patchwork of short lines, its widest cells drawn in coarse ones). Steps of 15°
/// keep a curve's lines from turning in visible kinks. A cell its neighbourhood bears out only
/// a little (`weight` below 1: directed less than [`BLEND`] over `flat.below`) turns that share
/// of the way to the flat angle first, so a form's weak edge meets a plain's lines gradually
/// instead of in patches of level lines.
fn on_the_ladder(f: Frame, flat: &FlatHatching, weight: f64) -> Frame {
    // The cell's turn from the flat angle, within a quarter turn either way (lines a half turn
    // apart are the same lines), `weight` of it taken, rounded to the ladder.
    let pi = std::f64::consts::PI;
    let diff = (f.angle - flat.angle).rem_euclid(pi);
    let diff = if diff > 0.5 * pi { diff - pi } else { diff };
    let turn = ((diff * weight) / ANGLE_STEP).round() * ANGLE_STEP;
    let angle = flat.angle + turn;
    let (sin, cos) = angle.sin_cos();
    let b = 2f64.powf(f.b.min(flat.largest).max(1e-9).log2().round());
    Frame {
        angle,
        cos,
        sin,
        a: f.a.max(b),
        b,
        anisotropy: f.anisotropy,
    }
}

/// How far over `flat.below` a cell's directed anisotropy must be for it to keep its own
/// direction whole (see [`on_the_ladder`]).
const BLEND: f32 = 0.25;

/// The step directed cells' angles are rounded to (see [`on_the_ladder`]).
const ANGLE_STEP: f64 = std::f64::consts::PI / 12.0;

/// Every cell's anisotropy as far as its neighbourhood bears it out: the doubled-angle
/// vectors `a·(cos 2θ, sin 2θ)` (`a` the anisotropy `1 − b/a`) averaged over the cell,
/// counted [`SELF_WEIGHT`] times, and the cells it touches (`neighbours`, each pair once),
/// then those means averaged the same way again (two rings of cells), and the result's length.
/// Along an edge, a chain of cells that share a direction keeps much of its own; a cell long
/// only by the grain of a plain (a brick's face), among round cells or cells turned every way,
/// keeps little: hatched in its own direction, such a cell would be a patch of lines at a
/// random angle in the plain's even hatching. Two rings, not one, so that a few cells a
/// texture's stains or fur happen to turn one way (a concrete floor) do not make a patch.
fn directed_anisotropy(frames: &[Frame], neighbours: &[[u32; 2]]) -> Vec<f32> {
    let own: Vec<[f64; 2]> = frames
        .iter()
        .map(|f| {
            let (s, c) = (2.0 * f.angle).sin_cos();
            [f64::from(f.anisotropy) * c, f64::from(f.anisotropy) * s]
        })
        .collect();
    let twice = ring_means(&ring_means(&own, neighbours), neighbours);
    twice
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt() as f32)
        .collect()
}

/// Every cell's `vectors` averaged with those of the cells it touches (`neighbours`, each
/// pair once), its own counted [`SELF_WEIGHT`] times.
fn ring_means(vectors: &[[f64; 2]], neighbours: &[[u32; 2]]) -> Vec<[f64; 2]> {
    let mut sums: Vec<([f64; 2], f64)> = vectors
        .iter()
        .map(|v| ([SELF_WEIGHT * v[0], SELF_WEIGHT * v[1]], SELF_WEIGHT))
        .collect();
    for &[a, b] in neighbours {
        for (i, j) in [(a, b), (b, a)] {
            let v = vectors[j as usize];
            let s = &mut sums[i as usize];
            s.0[0] += v[0];
            s.0[1] += v[1];
            s.1 += 1.0;
        }
    }
    sums.iter().map(|(v, n)| [v[0] / n, v[1] / n]).collect()
}

/// How many times a cell's own direction counts in [`directed_anisotropy`]'s means: with 2,
/// a cell of an edge's chain (two neighbours along it, the rest round) keeps two thirds of
/// its anisotropy over one ring.
const SELF_WEIGHT: f64 = 2.0;

/// The rung (a whole octave) of every flat cell (`octaves[i]`, log₂ of its short axis, is
/// `None` for a cell with a direction). A flat area is the flat cells joined by touching
/// neighbours whose sizes differ by less than [`SAME_AREA_OCTAVES`], or of which one is
/// `quiet` (no structure of its own: its size is the metric's answer to a structure beside
/// it, not the plain's: on their own rung, the cells round a mast in a plain sky would be a
/// finer, greyer aura round it); all its cells take one
/// rung: that of the median of every flat cell when the area's own median size is within half
/// an octave of it, else that of its own median. Rounding each cell on its own would cut
/// through the sizes of a flat area wherever they spread across a half octave (a grey wall
/// whose cells are 5.5 to 6.5 px straddles 2^2.5 = 5.66 px): its cells, hatched at 4 and 8 px
/// by turns, would read as patches. The metric's sizes change
/// gradually over an area and jump where a detail begins, so a galaxy's small cells in a black
/// sky keep their own, finer rung; grain makes many small areas of about one size, which the
/// shared median keeps on one rung.
fn flat_areas(
    octaves: &[Option<f64>],
    neighbours: &[[u32; 2]],
    quiet: Option<&[bool]>,
) -> Vec<Option<f64>> {
    let mut areas = DisjointSets::new(octaves.len());
    let quiet = |i: u32| quiet.is_some_and(|q| q.get(i as usize) == Some(&true));
    for &[a, b] in neighbours {
        let (Some(oa), Some(ob)) = (octaves[a as usize], octaves[b as usize]) else {
            continue;
        };
        if (oa - ob).abs() < SAME_AREA_OCTAVES || quiet(a) || quiet(b) {
            areas.join(a, b);
        }
    }
    let mut members: Vec<(u32, f64)> = octaves
        .iter()
        .enumerate()
        .filter_map(|(i, o)| o.map(|o| (i as u32, o)))
        .map(|(i, o)| (areas.root(i), o))
        .collect();
    members.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    let mut all: Vec<f64> = members.iter().map(|m| m.1).collect();
    let median = median_of(&mut all);
    let mut rung_of_root = vec![f64::NAN; octaves.len()];
    for area in members.chunk_by(|x, y| x.0 == y.0) {
        let own = area[area.len() / 2].1;
        let rung = if (own - median).abs() < 0.5 {
            median
        } else {
            own
        };
        rung_of_root[area[0].0 as usize] = rung.round();
    }
    (0..octaves.len() as u32)
        .map(|i| octaves[i as usize].map(|_| rung_of_root[areas.root(i) as usize]))
        .collect()
}

/// Touching flat cells whose sizes differ by less than this many octaves are one flat area:
/// the metric's gradation lets touching ellipses differ by up to about 0.58 octaves (a factor
/// 1.5), over a gradual change they differ far less.
const SAME_AREA_OCTAVES: f64 = 0.25;

/// The median of `values` (0 for none).
fn median_of(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let middle = values.len() / 2;
    *values.select_nth_unstable_by(middle, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    const FLAT: FlatHatching = FlatHatching {
        angle: -std::f64::consts::FRAC_PI_4,
        below: 0.25,
        largest: 100.0,
    };

    /// Cells `i` and `i + 1` touch, for `i` in `range`.
    fn chain(range: std::ops::Range<u32>) -> Vec<[u32; 2]> {
        range.map(|i| [i, i + 1]).collect()
    }

    #[test]
    fn a_flat_area_is_hatched_at_one_spacing() {
        // Round cells of a grey wall, 5.5 to 6.5 units across their short axis: rounded to
        // whole octaves they straddle 2^2.5 = 5.66 and split between spacings 4 and 8
        // (patches); as one area, they share its median's rung. Two cells about half their
        // size (a detail in the wall, touching it) keep their own, finer one.
        let mut metrics: Vec<Tensor> = (0..41)
            .map(|i| Tensor::isotropic(5.5 + f64::from(i) / 40.0))
            .collect();
        metrics.extend([Tensor::isotropic(3.0), Tensor::isotropic(3.2)]);
        let mut touching = chain(0..42);
        touching.push([0, 42]);
        let frames = cell_frames(&metrics, &touching, Some(FLAT), None);
        let wall: Vec<f64> = frames[..41].iter().map(|f| f.b).collect();
        assert!(wall.iter().all(|&b| b == wall[0]), "spacings {wall:?}");
        assert_eq!(wall[0], 8.0, "the median's whole octave");
        assert!(frames[41..].iter().all(|f| f.b == 4.0), "the detail's rung");
        assert!(frames.iter().all(|f| f.angle == FLAT.angle));
    }

    #[test]
    fn an_area_whose_sizes_spread_over_an_octave_takes_one_rung() {
        // A plain whose cells grow gradually from 3.5 to 8 units (1.2 octaves), and a second
        // one of 13 to 19 units, away from it: every cell of each plain shares one rung,
        // where rounding cell by cell, or taking the rung of the median of all flat cells
        // within half an octave of it, splits the first plain in two.
        let mut metrics: Vec<Tensor> = (0..60)
            .map(|i| Tensor::isotropic(3.5 * (8.0f64 / 3.5).powf(f64::from(i) / 59.0)))
            .collect();
        metrics.extend((0..25).map(|i| Tensor::isotropic(13.0 + f64::from(i) / 4.0)));
        let mut touching = chain(0..59);
        touching.extend(chain(60..84));
        let frames = cell_frames(&metrics, &touching, Some(FLAT), None);
        let first: Vec<f64> = frames[..60].iter().map(|f| f.b).collect();
        assert!(first.iter().all(|&b| b == first[0]), "spacings {first:?}");
        let second: Vec<f64> = frames[60..].iter().map(|f| f.b).collect();
        assert!(second.iter().all(|&b| b == 16.0), "spacings {second:?}");
        assert!(first[0] == 4.0 || first[0] == 8.0);
    }

    #[test]
    fn a_grainy_plain_takes_the_median_rung_whatever_its_cells_sizes() {
        // Neighbours whose sizes jump by a third of an octave at random (grain, not a
        // detail) make many small areas; those within half an octave of the median of all
        // flat cells take its rung, so the plain is hatched at one spacing, not in patches.
        // A long cell alone between them, which its neighbourhood hardly bears out, turns to
        // the flat angle, its size on the ladder.
        let mut state = 12345u32;
        let mut metrics: Vec<Tensor> = (0..200)
            .map(|_| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let jitter = f64::from(state >> 8) / f64::from(1u32 << 24) - 0.5;
                Tensor::isotropic(2f64.powf(2.4 + 0.8 * jitter))
            })
            .collect();
        metrics[100] = Tensor::from_eigen(0.3, 9.0, 3.0);
        let frames = cell_frames(&metrics, &chain(0..199), Some(FLAT), None);
        for (i, f) in frames.iter().enumerate() {
            if i == 100 {
                // A short axis of 3: two octaves.
                assert!((f.a - 9.0).abs() < 1e-9 && f.b == 4.0);
                assert_eq!(f.angle, FLAT.angle);
            } else {
                assert_eq!(f.b, 4.0, "cell {i}");
            }
        }
    }

    #[test]
    fn grain_turned_every_way_is_hatched_flat_and_an_edge_keeps_its_direction() {
        // An edge: a chain of cells along one direction (a/b = 8), each touching two round
        // cells on its sides. Grain: a 5 x 6 grid of slightly long cells (a/b = 1.47, over
        // `below`) turned by a right angle from each one to the next, as noise turns them.
        let mut metrics = vec![Tensor::from_eigen(0.3, 24.0, 3.0); 10];
        metrics.extend(vec![Tensor::isotropic(4.0); 20]);
        let mut touching = chain(0..9);
        touching.extend((0..10u32).flat_map(|i| [[i, 10 + 2 * i], [i, 11 + 2 * i]]));
        let grain = metrics.len() as u32;
        for r in 0..6u32 {
            for c in 0..5u32 {
                let angle = if (r + c) % 2 == 0 { 0.0 } else { FRAC_PI_2 };
                metrics.push(Tensor::from_eigen(angle, 4.4, 3.0));
                let i = grain + r * 5 + c;
                if c > 0 {
                    touching.push([i - 1, i]);
                }
                if r > 0 {
                    touching.push([i - 5, i]);
                }
            }
        }
        let frames = cell_frames(&metrics, &touching, Some(FLAT), None);
        // Its own direction is 62° from the flat angle: the ladder's 60°, or 45° where the
        // round cells beside it weaken it most (its ends).
        for f in &frames[..10] {
            let steps = ((f.angle - FLAT.angle) / ANGLE_STEP).round();
            assert!((f.angle - (FLAT.angle + steps * ANGLE_STEP)).abs() < 1e-9);
            assert!(steps == 3.0 || steps == 4.0, "{steps} steps");
            assert!((f.a - 24.0).abs() < 1e-9);
        }
        for (i, f) in frames[grain as usize..].iter().enumerate() {
            assert_eq!(f.angle, FLAT.angle, "grain cell {i}");
        }
    }

    #[test]
    fn directed_neighbours_a_little_apart_share_one_family_of_lines() {
        // A chain of cells along a gently turning edge (0.25 to 0.35 rad, 2:1, short axes 2.9
        // to 3.3): hatched each at its own angle and spacing, no two neighbours' lines met.
        // On the ladder they share one angle (60° from the flat angle) and one spacing (4),
        // and a cell turned 6° from the flat angle is hatched along it. A wide directed cell
        // takes the octave of `largest` (100, nearest 2⁷), as a wide flat cell does.
        let mut metrics: Vec<Tensor> = (0..11)
            .map(|i| {
                let t = f64::from(i) / 10.0;
                Tensor::from_eigen(0.25 + 0.1 * t, 2.0 * (2.9 + 0.4 * t), 2.9 + 0.4 * t)
            })
            .collect();
        metrics.push(Tensor::from_eigen(FLAT.angle + 0.1, 8.0, 4.0));
        metrics.push(Tensor::from_eigen(0.3, 800.0, 400.0));
        let frames = cell_frames(&metrics, &chain(0..10), Some(FLAT), None);
        for f in &frames[..11] {
            assert!((f.angle - (FLAT.angle + 4.0 * ANGLE_STEP)).abs() < 1e-9);
            assert_eq!(f.b, 4.0);
        }
        // (Angles a half turn apart draw the same lines.)
        assert!((frames[11].angle - FLAT.angle).sin().abs() < 1e-9);
        assert_eq!(frames[12].b, 128.0, "the octave of `largest`");
    }

    #[test]
    fn weakly_directed_cells_turn_part_of_the_way_to_the_flat_angle() {
        // Two forms, each a chain of like cells 62° from the flat angle: 2:1 (directed 0.5)
        // keeps the ladder's 60°; 1.6:1 (0.375, half way from `below` to `below + BLEND`)
        // turns half way, to 30°. Cut at `below` alone, a form's weak cells beside a plain
        // were a seam of lines 45° or more from the plain's.
        let mut metrics = vec![Tensor::from_eigen(0.3, 6.0, 3.0); 5];
        metrics.extend(vec![Tensor::from_eigen(0.3, 4.8, 3.0); 5]);
        let mut touching = chain(0..4);
        touching.extend(chain(5..9));
        let frames = cell_frames(&metrics, &touching, Some(FLAT), None);
        for (i, f) in frames.iter().enumerate() {
            let steps = if i < 5 { 4.0 } else { 2.0 };
            assert!(
                (f.angle - (FLAT.angle + steps * ANGLE_STEP)).abs() < 1e-9,
                "cell {i}: {} steps",
                (f.angle - FLAT.angle) / ANGLE_STEP
            );
        }
    }

    #[test]
    fn a_patch_that_grain_turned_one_way_is_hatched_flat() {
        // A 9 x 9 grid of slightly long cells (a/b = 1.47, over `below`) turned by a right
        // angle from each one to the next, as noise turns them, but for a 3 x 3 patch in its
        // middle that the grain happened to turn one way (a concrete floor's stain): hatched
        // along it, the patch was a square of lines at its own angle in the floor's even
        // hatching.
        let (n, patch) = (9u32, 3..6u32);
        let mut metrics = Vec::new();
        let mut touching = Vec::new();
        for r in 0..n {
            for c in 0..n {
                let angle = if patch.contains(&r) && patch.contains(&c) {
                    0.7
                } else if (r + c) % 2 == 0 {
                    0.0
                } else {
                    FRAC_PI_2
                };
                metrics.push(Tensor::from_eigen(angle, 4.4, 3.0));
                let i = r * n + c;
                if c > 0 {
                    touching.push([i - 1, i]);
                }
                if r > 0 {
                    touching.push([i - n, i]);
                }
            }
        }
        let frames = cell_frames(&metrics, &touching, Some(FLAT), None);
        let kept: Vec<u32> = (0..n * n)
            .filter(|&i| frames[i as usize].angle != FLAT.angle)
            .collect();
        // All but the patch's middle cell, whose whole first ring shares its direction (over
        // one ring, the middle and the four cells beside it kept theirs: a cross of lines).
        assert_eq!(kept, [4 * n + 4], "cells hatched their own way");
    }

    #[test]
    fn without_a_flat_angle_every_cell_keeps_its_own_frame() {
        let metrics = [Tensor::isotropic(5.5), Tensor::from_eigen(0.3, 6.0, 2.0)];
        let frames = cell_frames(&metrics, &[[0, 1]], None, None);
        assert_eq!(frames[0].b, 5.5);
        assert_eq!((frames[1].a, frames[1].b), (6.0, 2.0));
        assert!((frames[1].angle - 0.3).abs() < 1e-12);
    }
}
