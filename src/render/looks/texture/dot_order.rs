//! The dots of a stipple lattice ([`super::stipple`]) at a point, in the order a painter lays
//! them (paper section 6's textured cells, the pointillist's dabs): where dots overlap, each
//! lies above or below its neighbours by a hashed order, so the uppermost one that reaches a
//! point colours it and the one under it shows at its rim. The raster asks at every point of a
//! stippled cell, so a thread keeps the nine dots round the last point's lattice cell
//! ([`Neighbourhood`]) and the disc round the last point where its uppermost dot stays
//! uppermost (`Whole`). `f64` in domain units; coverage `f32`.

use super::stipple::dot;
use crate::render::support::colour::{mix, Linear};
use crate::render::support::rounding::floor;
use glam::DVec2;

/// The dots of a stipple lattice at a point, as a painter lays them one over another: `top`,
/// the coverage and centre of the uppermost dot that inks the point, and `under`, the next
/// one down (none where the top one inks it wholly, or where no other reaches it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DotsAt {
    pub(crate) top: (f32, DVec2),
    pub(crate) under: Option<(f32, DVec2)>,
}

impl DotsAt {
    /// The colour the dots lay at the point, `dab(centre)` being the colour of the dot centred
    /// at `centre`: the top one's, and at its rim the one's under it, each in the share of the
    /// ink it shows.
    #[must_use]
    pub(crate) fn ink(&self, dab: impl Fn(DVec2) -> Linear) -> Linear {
        let (a, top) = self.top;
        let c = dab(top);
        match self.under {
            Some((u, under)) if a < 1.0 => {
                let shown = (1.0 - a) * u;
                mix(c, dab(under), shown / (a + shown))
            }
            _ => c,
        }
    }

    /// The share of the point the dots ink together.
    #[must_use]
    pub(crate) fn cover(&self) -> f32 {
        let (a, _) = self.top;
        match self.under {
            Some((b, _)) => a + (1.0 - a) * b,
            None => a,
        }
    }
}

/// The dots at `local` (domain units in the cell's frame) of cell `site`, on a lattice of
/// period `s`, of radius `radius` periods, anti-aliased over a pixel of `px` domain units
/// ([`DotsAt`]; a point no dot reaches has a top of no coverage, centred at `local`). Dots of
/// no radius ink nothing (the anti-aliasing ramp alone would still lay half a pixel's ink at
/// each centre: faint specks on bare paper). Where the tone is `solid` (the point is inked
/// wholly whatever the dots cover) and the period is at least [`SHARP_DABS_FROM_PX`], the dot
/// under the top one is not looked for, and the top one's coverage may read 1 at its rim: where
/// two dabs meet, the upper one's edge is not smoothed over the lower.
///
/// Dots overlap where the tone asks for more than their lattice covers edge to edge: each
/// lies above or below its neighbours by a hashed order (`stipple::dot`), so every dot shows as
/// a disc or a disc with bites out of it, the round dabs of a brush. (Taking the point's own
/// lattice cell's dot wherever it covers cut the dabs of dark tones into the lattice's
/// squares: a 12 MP pointillist read as a pixelated picture.)
pub(crate) fn dots_at(
    local: DVec2,
    site: u32,
    s: f64,
    (radius, solid): (f64, bool),
    px: f64,
) -> DotsAt {
    let mut found = DotsAt {
        top: (0.0, local),
        under: None,
    };
    if radius <= 0.0 {
        return found;
    }
    let solid = solid && s >= SHARP_DABS_FROM_PX * px;
    let cell = DVec2::new(floor(local.x / s), floor(local.y / s));
    let r = s * radius;
    let reach = r + 0.5 * px;
    let (reach_squared, per_px) = (reach * reach, 1.0 / px);
    let core = r - 0.5 * px;
    let core_squared = if core > 0.0 { core * core } else { -1.0 };
    let key = (site, s.to_bits(), cell.x as i32, cell.y as i32);
    // Within the last point's uppermost dot's core (its reach, for a solid tone), and nearer
    // the last point than any dot above it comes to reaching, that dot is still the uppermost
    // and inks wholly (most points of a row).
    let inks_wholly = if solid { reach_squared } else { core_squared };
    if let Some(whole) = WHOLE.get() {
        if whole.key == key
            && whole.reach == reach
            && (local - whole.from).length_squared() < whole.clear_squared
            && (local - whole.top).length_squared() <= inks_wholly
        {
            found.top = (1.0, whole.top);
            return found;
        }
    }
    NEIGHBOURHOODS.with(|cache| {
        let mut cache = cache.borrow_mut();
        let dots = neighbourhood(&mut cache, key, cell, s);
        // Per dot, 0 where it does not reach the point, else its place in the painter's order
        // (plus one) over its place in the grid (ties: the later in the grid's row-by-row order
        // lies above, as the SVG draws them). Every distance measured and the uppermost taken
        // by a maximum, without a branch per dot.
        let mut keys = [0u64; 9];
        let mut d2s = [0.0; 9];
        for (k, (key, d2)) in keys.iter_mut().zip(&mut d2s).enumerate() {
            let (dx, dy) = (local.x - dots.xs[k], local.y - dots.ys[k]);
            *d2 = dx * dx + dy * dy;
            *key = u64::from(*d2 < reach_squared) * order_key(dots.above[k], k);
        }
        // Outside the dot's anti-aliased rim, or inside its solid core, the square of the
        // distance decides without a square root (most points of a stippled cell).
        let cover_of = |key: u64| {
            let k = (key & 0xF) as usize;
            let centre = DVec2::new(dots.xs[k], dots.ys[k]);
            let cover = if d2s[k] <= core_squared {
                1.0
            } else {
                ((r - d2s[k].sqrt()) * per_px + 0.5).clamp(0.0, 1.0) as f32
            };
            (cover, centre)
        };
        let top = keys.iter().copied().fold(0, u64::max);
        let mut whole = None;
        if top != 0 {
            found.top = cover_of(top);
            if found.top.0 < 1.0 && !solid {
                let under = keys.iter().copied().filter(|&k| k != top).fold(0, u64::max);
                if under != 0 {
                    found.under = Some(cover_of(under));
                }
            } else {
                // How far the point is from the reach of the nearest dot above the top one.
                let nearest = (0..9)
                    .filter(|&k| order_key(dots.above[k], k) > top)
                    .map(|k| d2s[k])
                    .fold(f64::INFINITY, f64::min);
                let clear = nearest.sqrt() - reach;
                whole = Some(Whole {
                    key,
                    reach,
                    from: local,
                    top: found.top.1,
                    clear_squared: clear * clear,
                });
            }
        }
        WHOLE.set(whole);
    });
    found
}

/// The stipple period in output pixels from which dabs of a solid tone meet without the upper
/// one's edge smoothed over the lower ([`dots_at`]): a pixel's step against a dab at least this
/// wide does not show, and skipping it saves time at 12 MP; smaller dabs (a photo of up to a
/// megapixel) keep it, or their tone suffers.
const SHARP_DABS_FROM_PX: f64 = 8.0;

/// The dots (domain units in the cell's frame) of lattice cell `cell` of `site`'s cell,
/// period `s`, and of its eight neighbours (jitter can reach across), row by row: kept from
/// the last point when it fell in the same lattice cell (a row's consecutive points), and
/// otherwise sharing with it the dots both neighbourhoods hold (a row steps into the next
/// lattice cell: six of the nine), so only the new ones are hashed.
#[inline]
fn neighbourhood(
    last: &mut Neighbourhood,
    key: (u32, u64, i32, i32),
    cell: DVec2,
    s: f64,
) -> &Neighbourhood {
    if last.key != Some(key) {
        step_to(last, key, cell, s);
    }
    last
}

/// [`neighbourhood`] in a lattice cell other than the last one's: its dots, hashing only those
/// the last neighbourhood does not hold.
#[cold]
#[inline(never)]
fn step_to(last: &mut Neighbourhood, key: (u32, u64, i32, i32), cell: DVec2, s: f64) {
    let (site, _, cx, cy) = key;
    let shift = match last.key {
        Some((site_was, s_was, x, y)) if site_was == site && s_was == key.1 => {
            Some((cx - x, cy - y))
        }
        _ => None,
    };
    let was = (last.above, last.xs, last.ys);
    for i in 0..9 {
        let (dx, dy) = (i as i32 % 3 - 1, i as i32 / 3 - 1);
        match shift {
            Some((x, y)) if (dx + x).abs() <= 1 && (dy + y).abs() <= 1 => {
                let j = ((dy + y + 1) * 3 + dx + x + 1) as usize;
                (last.above[i], last.xs[i], last.ys[i]) = (was.0[j], was.1[j], was.2[j]);
            }
            _ => {
                let (above, centre) = dot(site, cell + DVec2::new(f64::from(dx), f64::from(dy)));
                (last.above[i], last.xs[i], last.ys[i]) = (above, centre.x * s, centre.y * s);
            }
        }
    }
    last.key = Some(key);
}

/// The last lattice cell [`neighbourhood`] was asked for: its key (site, period's bits, cell)
/// and its nine dots row by row, each with its place in the painter's order and its centre
/// (x and y apart). A function of its key alone, so renders share it.
struct Neighbourhood {
    key: Option<(u32, u64, i32, i32)>,
    above: [u32; 9],
    xs: [f64; 9],
    ys: [f64; 9],
}

/// A disc round a point `from` of lattice cell `key` ([`Neighbourhood`]'s) that no dot above
/// the point's uppermost dot (centred at `top`) reaches: the radius is the least of their
/// distances less their `reach`, given squared.
#[derive(Clone, Copy)]
struct Whole {
    key: (u32, u64, i32, i32),
    reach: f64,
    from: DVec2,
    top: DVec2,
    clear_squared: f64,
}

/// A dot's key for the painter's order: its place in it (plus one, so that 0 is below every
/// dot) over its place `k` in the grid row by row (ties: the later lies above, as the SVG
/// draws them).
fn order_key(above: u32, k: usize) -> u64 {
    ((u64::from(above) + 1) << 4) | k as u64
}

thread_local! {
    /// Where a thread's last point's uppermost dot inks wholly and no other lies above it.
    static WHOLE: std::cell::Cell<Option<Whole>> = const { std::cell::Cell::new(None) };
    /// A thread's last [`Neighbourhood`].
    static NEIGHBOURHOODS: std::cell::RefCell<Neighbourhood> =
        const {
            std::cell::RefCell::new(Neighbourhood {
                key: None,
                above: [0; 9],
                xs: [0.0; 9],
                ys: [0.0; 9],
            })
        };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::support::hash::site_hash;

    #[test]
    fn dots_lie_one_over_another_in_their_hashed_order() {
        // Against a brute force over the 5 × 5 lattice cells round each point: the top dot is
        // the uppermost (by `dot`'s order) of those that ink the point, `under` the next one
        // down where the top one leaves some of it. Points row by row (a row's lattice cells in
        // turn, as the raster asks) and then scattered (a new neighbourhood each time).
        let (s, px) = (3.0, 0.25);
        let mut rows: Vec<DVec2> = Vec::new();
        for j in 0..70 {
            for i in 0..70 {
                rows.push(DVec2::new(
                    -10.0 + 0.29 * f64::from(i),
                    -10.0 + 0.29 * f64::from(j),
                ));
            }
        }
        let scattered: Vec<DVec2> = (0..3000u32)
            .map(|k| {
                let h = |salt: u64| f64::from(site_hash(k, salt)) * 24.0 - 12.0;
                DVec2::new(h(1), h(9))
            })
            .collect();
        for site in [0u32, 5, 77] {
            for radius in [0.3, 0.6, 0.9] {
                let (r, mut elsewhere, mut inked) = (s * radius, 0, 0);
                for &p in rows.iter().chain(&scattered) {
                    let got = dots_at(p, site, s, (radius, false), px);
                    let cell = DVec2::new(floor(p.x / s), floor(p.y / s));
                    let mut reaching: Vec<((u32, i32, i32), f32, DVec2)> = Vec::new();
                    for dy in -2..=2 {
                        for dx in -2..=2 {
                            let (above, c) = dot(site, cell + DVec2::new(dx.into(), dy.into()));
                            let d = (p - c * s).length();
                            let cover = ((r - d) / px + 0.5).clamp(0.0, 1.0) as f32;
                            if cover > 0.0 {
                                // Ties of the order: the later row by row lies above.
                                reaching.push(((above, dy, dx), cover, c * s));
                            }
                        }
                    }
                    reaching.sort_by_key(|&(above, ..)| std::cmp::Reverse(above));
                    let want = match reaching.as_slice() {
                        [] => (0.0, p),
                        [(_, a, c), ..] => (*a, *c),
                    };
                    assert_eq!(got.top.1, want.1, "{p} at radius {radius}");
                    assert!((got.top.0 - want.0).abs() < 1e-5, "{p}: {got:?}");
                    let under = match reaching.as_slice() {
                        [(_, a, _), (_, b, c), ..] if *a < 1.0 => Some((*b, *c)),
                        _ => None,
                    };
                    assert_eq!(got.under.map(|u| u.1), under.map(|u| u.1), "{p}");
                    // A solid tone asks only for the uppermost dot.
                    let solid = dots_at(p, site, s, (radius, true), px);
                    assert_eq!(solid.top.1, want.1, "{p}, solid");
                    assert_eq!(solid.under, None);
                    // Dabs under SHARP_DABS_FROM_PX pixels keep the one under the top one.
                    let small = 2.0 * s / SHARP_DABS_FROM_PX;
                    let smoothed = dots_at(p, site, s, (radius, false), small);
                    assert_eq!(dots_at(p, site, s, (radius, true), small), smoothed, "{p}");
                    if got.top.0 >= 1.0 {
                        inked += 1;
                        let own = got.top.1 / s;
                        elsewhere += usize::from(floor(own.x) != cell.x || floor(own.y) != cell.y);
                    }
                }
                if radius > 0.8 {
                    // Dabs that overlap show as discs, not as their lattice's squares: about
                    // half the points lies under a neighbouring cell's dab (measured: 51–54 %;
                    // taking the point's own cell's dot wherever it inks, 0.2 %).
                    let share = elsewhere as f64 / inked as f64;
                    assert!(share > 0.3, "{share}");
                }
            }
        }
    }
}
