//! The stipple lattice of the stipple and pointillist looks (paper section 6's textured cells):
//! in a cell's frame, one dot per lattice cell of one period, its centre jittered by up to
//! ±0.3 periods (`dot_centre`), all of one radius for the cell's tone (`stipple_radius`,
//! measured on the lattice itself so the dots ink the share of paper the tone asks for), laid
//! one over another in a hashed order where they overlap (`dot_order.rs`), as a painter lays
//! dabs. The raster ([`super`]) and the SVG ([`crate::render::vector`]) place the same dots in
//! the same order, and give the pointillist's each its own colour (`Dab`). `f64` in domain
//! units; coverage and colour factors `f32`.

use crate::render::support::colour::Linear;
use crate::render::support::hash::{salt, site_bits};
use crate::render::support::rounding::floor;
use glam::DVec2;

/// Centre of the stipple dot of lattice cell `c` (in lattice periods) in `site`'s cell: the
/// cell's middle, jittered by up to ±0.3 periods.
pub(crate) fn dot_centre(site: u32, c: DVec2) -> DVec2 {
    dot(site, c).1
}

/// The stipple dot of lattice cell `c` (in lattice periods) of `site`'s cell: where it lies
/// among its neighbours (higher above; a painter's order of the dabs) and its centre
/// ([`dot_centre`]). One hash gives both: 24 bits for each of the centre's two offsets, 16
/// for the order.
pub(crate) fn dot(site: u32, c: DVec2) -> (u32, DVec2) {
    let key = site.wrapping_mul(7919)
        ^ ((c.x as i32 as u32).wrapping_mul(73_856_093))
        ^ ((c.y as i32 as u32).wrapping_mul(19_349_663));
    let bits = site_bits(key, salt::STIPPLE);
    let unit = |shift: u32| f64::from(((bits >> shift) & 0xFF_FFFF) as u32) / f64::from(1u32 << 24);
    let offset = DVec2::new(0.5 + 0.6 * (unit(40) - 0.5), 0.5 + 0.6 * (unit(16) - 0.5));
    ((bits & 0xFFFF) as u32, c + offset)
}

/// Steps of the stipple radius table, and the largest radius it holds (lattice periods).
const DOT_STEPS: usize = 64;
const DOT_MAX_RADIUS: f64 = 1.2;

/// The dot radius, in lattice periods, that inks a share `cover` of the paper. Dots on a
/// jittered lattice overlap and leave gaps, so `√(cover/π)` falls short of dark tones (no
/// radius under half a period can cover more than π/4); the share each radius really inks is
/// measured once on the lattice itself (its own jitter, its ±1 neighbourhood) and inverted.
pub(crate) fn stipple_radius(cover: f32) -> f64 {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    let inked = TABLE.get_or_init(|| {
        // 24 × 24 lattice cells, 6 × 6 points each. A point is inked at radius r when its
        // nearest dot (of its lattice cell and the eight around it) is closer than r: the
        // distances are measured once, then counted for every radius (measuring them again
        // for each of the 65 radii took 0.1 s, once per process).
        let (cells, points) = (24usize, 6usize);
        let mut nearest = Vec::with_capacity(cells * cells * points * points);
        for cy in 0..cells {
            for cx in 0..cells {
                for j in 0..points {
                    for i in 0..points {
                        let q = DVec2::new(
                            cx as f64 + (i as f64 + 0.5) / points as f64,
                            cy as f64 + (j as f64 + 0.5) / points as f64,
                        );
                        let cell = DVec2::new(floor(q.x), floor(q.y));
                        let mut d = f64::INFINITY;
                        for dy in -1..=1 {
                            for dx in -1..=1 {
                                let c = cell + DVec2::new(f64::from(dx), f64::from(dy));
                                d = d.min((q - dot_centre(0, c)).length());
                            }
                        }
                        nearest.push(d);
                    }
                }
            }
        }
        (0..=DOT_STEPS)
            .map(|k| {
                let r = DOT_MAX_RADIUS * k as f64 / DOT_STEPS as f64;
                let hits = nearest.iter().filter(|&&d| d < r).count();
                hits as f64 / nearest.len() as f64
            })
            .collect()
    });
    let c = f64::from(cover.clamp(0.0, 1.0));
    // The table grows with the radius: the first radius that inks at least `c`, by bisection
    // (this runs at every raster point of a stippled cell).
    match inked.partition_point(|&v| v < c) {
        0 => 0.0,
        k if k > DOT_STEPS => DOT_MAX_RADIUS,
        k => {
            let (lo, hi) = (inked[k - 1], inked[k]);
            let t = if hi > lo { (c - lo) / (hi - lo) } else { 1.0 };
            DOT_MAX_RADIUS * ((k - 1) as f64 + t) / DOT_STEPS as f64
        }
    }
}

/// A pointillist dab (a stipple dot with [`Ink::Pixel`](super::Ink::Pixel)): one
/// stroke of one colour, the photo's at its centre, drawn for this dot alone a little lighter
/// or darker than the photo (within ±[`DOT_LIGHT_JITTER`]) and, in proportion to the photo's
/// saturation, a little off its hue (each channel within ±[`DOT_HUE_JITTER`]). Neighbouring
/// dots read as separate dabs, as in divisionist painting. A grey stays grey (dabs of its own
/// lightness, as charcoal would lay them): shifted channel by channel, a grey sky or a face
/// turned into pastel confetti. Where the dab crosses an edge of the photo it gives way to the
/// photo ([`Dab::colour_over`]). The raster and the SVG use the same colours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dab {
    /// The photo's colour at the dab's centre, and the square roots of its channels.
    flat: Linear,
    roots: [f32; 3],
    /// What the dab keeps of the photo (`1 − darken`), and its factor per channel.
    keep: f32,
    factors: [f32; 3],
    /// Its one colour, where no edge cuts it.
    colour: Linear,
    /// Per channel, the photo's values whose square roots are within [`DAB_EDGE`]`.0` of
    /// `roots` (lowest, highest): where every channel is, no edge cuts the dab.
    uncut: [[f32; 2]; 3],
}

impl Dab {
    /// The dab of cell `site` centred at `centre` (domain units in the cell's frame) over the
    /// photo's colour `flat` there, darkened by `darken`.
    #[must_use]
    pub(crate) fn new(site: u32, centre: DVec2, flat: Linear, darken: f32) -> Dab {
        // Four values in [−1, 1] from one hash, 16 bits each: lightness, red, green, blue.
        let bits = site_bits(dot_key(site, centre), salt::DOT_COLOUR);
        let spread = |k: usize| f32::from((bits >> (16 * k)) as u16) / 32_767.5 - 1.0;
        let max = flat[0].max(flat[1]).max(flat[2]);
        let min = flat[0].min(flat[1]).min(flat[2]);
        let saturation = if max > 0.0 { (max - min) / max } else { 0.0 };
        let light = 1.0 + DOT_LIGHT_JITTER * spread(0);
        let hue = DOT_HUE_JITTER * saturation;
        let keep = 1.0 - darken;
        let factors: [f32; 3] = std::array::from_fn(|i| light * (1.0 + hue * spread(i + 1)));
        let roots = flat.map(|v| v.max(0.0).sqrt());
        let edge = DAB_EDGE.0;
        Dab {
            flat,
            roots,
            keep,
            factors,
            colour: std::array::from_fn(|i| (flat[i] * keep * factors[i]).clamp(0.0, 1.0)),
            uncut: roots.map(|r| [(r - edge).max(0.0).powi(2), (r + edge).powi(2)]),
        }
    }

    /// The dab's colour at a point where the photo is `here`. Away from edges that is the
    /// dab's one colour. Where `here` differs from its centre's by an edge, the dab gives way
    /// to the photo, so it is cut by the edges it crosses instead of smearing them (eyes,
    /// teeth, lettering). The difference is the largest over the channels of their square
    /// roots (about perceptual: dark edges count as light ones do): one colour up to
    /// [`DAB_EDGE`]`.0`, the photo's own from [`DAB_EDGE`]`.1` on, linear between.
    #[must_use]
    pub(crate) fn colour_over(&self, here: Linear) -> Linear {
        // Most points of a dab: no square root needed to know no edge cuts it there. (Where
        // rounding puts a point on the other side of the band's end than the roots would,
        // both ways give the dab's colour to far under a level: the 12 MP pointillist is the
        // same picture, 5 % faster.)
        if (0..3).all(|k| here[k] >= self.uncut[k][0] && here[k] <= self.uncut[k][1]) {
            return self.colour;
        }
        self.colour_by_roots(here)
    }

    /// [`Self::colour_over`] by its definition: a square root per channel at every point.
    fn colour_by_roots(&self, here: Linear) -> Linear {
        let diff = (0..3)
            .map(|k| (self.roots[k] - here[k].max(0.0).sqrt()).abs())
            .fold(0.0f32, f32::max);
        let (lo, hi) = DAB_EDGE;
        if diff <= lo {
            return self.colour;
        }
        let t = ((diff - lo) * (1.0 / (hi - lo))).min(1.0);
        std::array::from_fn(|i| {
            let under = self.flat[i] + (here[i] - self.flat[i]) * t;
            (under * self.keep * self.factors[i]).clamp(0.0, 1.0)
        })
    }
}

/// The one colour of the dab of cell `site` centred at `centre` over the photo's colour
/// `under` there, darkened by `darken` ([`Dab`]): what the SVG lays for the dot.
#[must_use]
pub(crate) fn dab_colour(site: u32, centre: DVec2, under: Linear, darken: f32) -> Linear {
    Dab::new(site, centre, under, darken).colour
}

/// The differences (square roots of linear channels) between the photo at a point and at its
/// dab's centre over which the dab gives way to the photo ([`Dab::colour_over`]). Overlapping
/// round dabs (`dot_order.rs`) show a large area each, so a wide band would smear the faint
/// edges under them; a narrower one (0.02, 0.06) would melt the dabs of a face's soft shading
/// into it.
const DAB_EDGE: (f32, f32) = (0.03, 0.08);

/// The pointillist dab of cell `site` centred at `centre` in render `render`
/// ([`next_render`]), `make()` making it: made once for the consecutive points of a thread
/// that fall in one dab (most points of a row), which otherwise each read the photo at its
/// centre and hashed the dot again. The dab `make` gives, whatever the thread or the order of
/// the points.
pub(crate) fn dab_at(render: u32, site: u32, centre: DVec2, make: impl FnOnce() -> Dab) -> Dab {
    LAST_DABS.with(|last| {
        let mut last = last.borrow_mut();
        let key = (render, site, centre);
        for i in 0..2 {
            if let Some((k, dab)) = &last.slots[i] {
                if *k == key {
                    let dab = *dab;
                    last.latest = i;
                    return dab;
                }
            }
        }
        let dab = make();
        let older = 1 - last.latest;
        last.slots[older] = Some((key, dab));
        last.latest = older;
        dab
    })
}

/// The last two dabs a thread used ([`dab_at`]), and which of them it used last.
struct LastDabs {
    slots: [Option<(DabKey, Dab)>; 2],
    latest: usize,
}

/// A number no other render of this process has, for [`dab_at`]'s key: a thread's last dab
/// is never taken from another picture.
pub(crate) fn next_render() -> u32 {
    static RENDERS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    RENDERS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

type DabKey = (u32, u32, DVec2);

thread_local! {
    /// The last two dabs a thread used ([`dab_at`]): at the rim of a dab the one under it
    /// shows too.
    static LAST_DABS: std::cell::RefCell<LastDabs> = const {
        std::cell::RefCell::new(LastDabs {
            slots: [None, None],
            latest: 0,
        })
    };
}

/// How far a pointillist dab's lightness may move from the photo's, as a share of it (every
/// channel alike, which keeps edges better than a shift per channel): dabs that show at arm's
/// length.
const DOT_LIGHT_JITTER: f32 = 0.1;

/// How far each channel of a pointillist dab of a fully saturated colour may move from the
/// photo's, as a share of it (less for paler colours, none for greys).
const DOT_HUE_JITTER: f32 = 0.2;

/// A hash key of the dot centred at `centre` (a cell's frame, domain units) of cell `site`.
fn dot_key(site: u32, centre: DVec2) -> u32 {
    // Dot centres are distinct to far better than 1/64 of a domain unit.
    let (x, y) = (
        (centre.x * 64.0) as i64 as u32,
        (centre.y * 64.0) as i64 as u32,
    );
    site.wrapping_mul(7919) ^ x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)
}

#[cfg(test)]
mod tests {
    use super::super::dot_order::dots_at;
    use super::*;

    #[test]
    fn pointillist_dabs_each_take_their_own_colour_within_the_jitter() {
        // Every dot of a cell's lattice over a grey and over a saturated orange: the same
        // colour for the same dot and over the whole dot (any point of it finds the same dot);
        // over the grey, grey dabs within ±DOT_LIGHT_JITTER of its lightness, spread over most
        // of that range; over the orange, each channel within the lightness and hue jitters,
        // the hue visibly varied.
        let (s, radius, px) = (3.0, 0.45, 1.0);
        let (grey, orange) = ([0.4f32; 3], [0.8f32, 0.3, 0.05]);
        let (mut lights, mut hues) = (Vec::new(), Vec::new());
        for cy in -4..4 {
            for cx in -4..4 {
                let c = dot_centre(7, DVec2::new(f64::from(cx), f64::from(cy))) * s;
                let g = dab_colour(7, c, grey, 0.0);
                assert_eq!(g, dab_colour(7, c, grey, 0.0));
                assert!(g[0] == g[1] && g[1] == g[2], "a grey dab is grey: {g:?}");
                let light = g[0] / grey[0];
                assert!((light - 1.0).abs() <= DOT_LIGHT_JITTER + 1e-6, "{light}");
                lights.push(light);
                let o = dab_colour(7, c, orange, 0.0);
                let factors: Vec<f32> = o.iter().zip(orange).map(|(v, u)| v / u).collect();
                let (most, least) = (
                    (1.0 + DOT_LIGHT_JITTER) * (1.0 + DOT_HUE_JITTER) + 1e-6,
                    (1.0 - DOT_LIGHT_JITTER) * (1.0 - DOT_HUE_JITTER) - 1e-6,
                );
                assert!(
                    factors.iter().all(|&f| (least..=most).contains(&f)),
                    "{o:?}"
                );
                hues.push(factors[0] / factors[2]);
                for offset in [DVec2::ZERO, DVec2::new(0.4, 0.3), DVec2::new(-0.5, 0.2)] {
                    let (cover, centre) = dots_at(c + offset, 7, s, (radius, false), px).top;
                    if cover >= 1.0 {
                        assert_eq!(dab_colour(7, centre, orange, 0.0), o, "one colour a dot");
                    }
                }
            }
        }
        let range = |v: &[f32]| {
            v.iter()
                .fold((f32::MAX, f32::MIN), |(a, b), &x| (a.min(x), b.max(x)))
        };
        let (lo, hi) = range(&lights);
        assert!(
            lo < 1.0 - 0.8 * DOT_LIGHT_JITTER && hi > 1.0 + 0.8 * DOT_LIGHT_JITTER,
            "lightness {lo} to {hi}"
        );
        let (lo, hi) = range(&hues);
        assert!(hi / lo > 1.3, "red over blue {lo} to {hi}");
    }

    #[test]
    fn a_dab_is_one_colour_in_a_soft_photo_and_is_cut_by_its_edges() {
        // A dab centred on a grey of 0.2 (linear, √ 0.447): over the photo's soft shading
        // round it (0.18 to 0.22, √ within 0.025) it lays its own one colour, the photo's at
        // its centre with the dab's lightness; across an edge to 0.6 (√ 0.775) it lays the
        // photo there, with the same lightness; at 0.25 (√ 0.5), on the ramp, a share of
        // each.
        let centre = DVec2::new(1.0, 2.0);
        let dab = Dab::new(3, centre, [0.2; 3], 0.0);
        let light = dab.colour_over([0.2; 3])[0] / 0.2;
        assert!((light - 1.0).abs() <= DOT_LIGHT_JITTER + 1e-6, "{light}");
        for soft in [0.18f32, 0.19, 0.21, 0.22] {
            let c = dab.colour_over([soft; 3]);
            assert!(
                (c[0] - 0.2 * light).abs() < 1e-6,
                "{soft}: {c:?}, one colour a dab"
            );
        }
        let across = dab.colour_over([0.6; 3]);
        assert!(
            (across[0] - 0.6 * light).abs() < 1e-6,
            "{across:?}, the photo's past the edge"
        );
        let between = dab.colour_over([0.25; 3])[0] / light;
        assert!(
            between > 0.2 + 1e-3 && between < 0.25 - 1e-3,
            "{between}, on the ramp"
        );
        // A channel alone (a red edge on a grey) cuts the dab too.
        let red = dab.colour_over([0.6, 0.2, 0.2]);
        assert!((red[0] - 0.6 * light).abs() < 1e-6, "{red:?}");
        // The SVG's one colour per dot is the raster's away from edges.
        assert_eq!(
            dab_colour(3, centre, [0.2; 3], 0.0),
            dab.colour_over([0.21; 3])
        );
    }

    #[test]
    fn the_uncut_band_gives_what_the_square_roots_give() {
        let levels = [0.0f32, 0.001, 0.003, 0.02, 0.1, 0.2, 0.35, 0.5, 0.8, 1.0];
        let mut cut = 0;
        for (n, &a) in levels.iter().enumerate() {
            for &b in &levels {
                let dab = Dab::new(n as u32, DVec2::new(0.3, 0.7), [a, b, 0.4], 0.1);
                for &x in &levels {
                    for &y in &levels {
                        // Points near the band's ends too: each level nudged a little.
                        for nudge in [-0.0005f32, 0.0, 0.0005] {
                            let here = [x + nudge, y, 0.4 + nudge];
                            let (got, want) = (dab.colour_over(here), dab.colour_by_roots(here));
                            let diff = (0..3).map(|k| (got[k] - want[k]).abs()).fold(0.0, f32::max);
                            assert!(
                                diff < 1e-5,
                                "{:?} over {here:?}: {got:?} {want:?}",
                                dab.flat
                            );
                            cut += usize::from(want != dab.colour);
                        }
                    }
                }
            }
        }
        assert!(cut > 1000, "edges cut the dabs at {cut} points");
    }

    #[test]
    fn the_dab_a_thread_keeps_is_the_dab_of_the_point() {
        // Points of the same dab reuse it (the photo at its centre is read once); another
        // dot, cell or render makes its own.
        let reads = std::cell::Cell::new(0);
        let read = |c: Linear| {
            reads.set(reads.get() + 1);
            c
        };
        let (render, other) = (next_render(), next_render());
        let centre = DVec2::new(0.5, 0.5);
        let a = dab_at(render, 1, centre, || {
            Dab::new(1, centre, read([0.3; 3]), 0.0)
        });
        assert_eq!(a, Dab::new(1, centre, [0.3; 3], 0.0));
        let again = dab_at(render, 1, centre, || {
            Dab::new(1, centre, read([0.9; 3]), 0.0)
        });
        assert_eq!(again, a);
        assert_eq!(reads.get(), 1);
        let cases = [
            (render, 2, centre),
            (render, 1, DVec2::new(0.5, 1.5)),
            (other, 1, centre),
        ];
        for (r, site, c) in cases {
            assert_eq!(
                dab_at(r, site, c, || Dab::new(site, c, read([0.9; 3]), 0.0)),
                Dab::new(site, c, [0.9; 3], 0.0)
            );
        }
        assert_eq!(reads.get(), 4);
    }
}
