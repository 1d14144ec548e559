//! A tensor field on a regular grid over a rectangular domain in pixel coordinates, with
//! bilinear component-wise interpolation (paper section 3).
//!
//! Coordinates: x to the right, y down, the domain is `[0, width] × [0, height]` in pixels.
//! Grid node `(c, r)` sits at `((c + 0.5)·spacing, (r + 0.5)·spacing)`, so with `spacing = 1`
//! node `(c, r)` is the centre of pixel `(c, r)`. A coarser spacing lets a field computed at an
//! analysis resolution cover a larger photo. Outside the outermost node centres the field is
//! clamped (constant extension). Components are stored as `f32` triples `(t11, t12, t22)`,
//! row-major, which is also the `.npy` layout `(H, W, 3)`.

use super::tensor::Tensor;
use glam::DVec2;

/// A symmetric tensor per grid node over a rectangular pixel domain.
#[derive(Clone, Debug, PartialEq)]
pub struct TensorField {
    cols: usize,
    rows: usize,
    spacing: f64,
    domain: DVec2,
    data: Vec<[f32; 3]>,
}

impl TensorField {
    /// A field of `cols × rows` nodes with one node per pixel (`spacing = 1`).
    ///
    /// # Panics
    /// If `data.len() != cols·rows` or either size is zero (a programming error: inputs are
    /// validated before a field is built).
    #[must_use]
    pub fn new(cols: usize, rows: usize, data: Vec<[f32; 3]>) -> Self {
        Self::with_spacing(cols, rows, 1.0, (cols as f64, rows as f64), data)
    }

    /// A field of `cols × rows` nodes `spacing` pixels apart over a domain of `domain` pixels
    /// (`domain ≈ nodes · spacing`; it may be a little smaller when a photo's size is not a
    /// multiple of the spacing).
    ///
    /// # Panics
    /// If `data.len() != cols·rows`, a size is zero or the spacing is not positive.
    #[must_use]
    pub fn with_spacing(
        cols: usize,
        rows: usize,
        spacing: f64,
        domain: (f64, f64),
        data: Vec<[f32; 3]>,
    ) -> Self {
        assert!(cols > 0 && rows > 0, "empty tensor field");
        assert_eq!(data.len(), cols * rows, "tensor field data length");
        assert!(spacing > 0.0, "grid spacing must be positive");
        TensorField {
            cols,
            rows,
            spacing,
            domain: DVec2::new(domain.0, domain.1),
            data,
        }
    }

    /// A field of one tensor everywhere, one node per pixel.
    #[must_use]
    pub fn constant(width: usize, height: usize, t: Tensor) -> Self {
        Self::new(width, height, vec![t.to_f32(); width * height])
    }

    /// A field built from a function of the node position in pixels, one node per pixel,
    /// evaluated in parallel.
    #[must_use]
    pub fn from_fn(width: usize, height: usize, f: impl Fn(DVec2) -> Tensor + Sync) -> Self {
        use rayon::prelude::*;
        let mut data = vec![[0.0f32; 3]; width * height];
        data.par_chunks_mut(width).enumerate().for_each(|(r, row)| {
            for (c, out) in row.iter_mut().enumerate() {
                *out = f(DVec2::new(c as f64 + 0.5, r as f64 + 0.5)).to_f32();
            }
        });
        Self::new(width, height, data)
    }

    /// Number of grid columns.
    #[must_use]
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Number of grid rows.
    #[must_use]
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Distance between grid nodes in pixels.
    #[must_use]
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Size of the domain in pixels `(width, height)`.
    #[must_use]
    pub fn domain(&self) -> DVec2 {
        self.domain
    }

    /// Diagonal of the domain in pixels.
    #[must_use]
    pub fn diagonal(&self) -> f64 {
        self.domain.length()
    }

    /// Row-major node values `(t11, t12, t22)`.
    #[must_use]
    pub fn data(&self) -> &[[f32; 3]] {
        &self.data
    }

    /// Mutable row-major node values.
    pub fn data_mut(&mut self) -> &mut [[f32; 3]] {
        &mut self.data
    }

    /// The tensor stored at node `(c, r)`.
    #[must_use]
    pub fn node(&self, c: usize, r: usize) -> Tensor {
        Tensor::from_f32(self.data[r * self.cols + c])
    }

    /// Position of node `(c, r)` in pixels.
    #[must_use]
    pub fn node_position(&self, c: usize, r: usize) -> DVec2 {
        DVec2::new(c as f64 + 0.5, r as f64 + 0.5) * self.spacing
    }

    /// Bilinear component-wise interpolation at `p` (pixels), clamped at the border.
    /// A non-finite `p` is treated as the domain's origin. The weights are `f64`, the blend of
    /// the stored `f32` values `f32` (their own precision), the result `f64`.
    #[inline]
    #[must_use]
    pub fn sample(&self, p: DVec2) -> Tensor {
        let (c0, c1, tx) = axis_weights(p.x / self.spacing, self.cols);
        let (r0, r1, ty) = axis_weights(p.y / self.spacing, self.rows);
        let (tx, ty) = (tx as f32, ty as f32);
        let (top, bottom) = (r0 * self.cols, r1 * self.cols);
        let (a, b) = (self.data[top + c0], self.data[top + c1]);
        let (c, d) = (self.data[bottom + c0], self.data[bottom + c1]);
        let blend = |k: usize| {
            let upper = a[k] + (b[k] - a[k]) * tx;
            let lower = c[k] + (d[k] - c[k]) * tx;
            f64::from(upper + (lower - upper) * ty)
        };
        Tensor::new(blend(0), blend(1), blend(2))
    }

    /// The same field resampled to one node per pixel of a `width × height` domain (used to
    /// write a field computed at analysis resolution at the photo's own size).
    #[must_use]
    pub fn resampled(&self, width: usize, height: usize) -> TensorField {
        if self.spacing == 1.0 && self.cols == width && self.rows == height {
            return self.clone();
        }
        let sx = self.domain.x / width as f64;
        let sy = self.domain.y / height as f64;
        let mut out = Self::from_fn(width, height, |p| {
            self.sample(DVec2::new(p.x * sx, p.y * sy))
        });
        out.domain = DVec2::new(width as f64, height as f64);
        out
    }

    /// This field read at every node of a `cols × rows` grid of `spacing` over the same
    /// domain: each node's value is [`Self::sample`]'s at the node, bit for bit, with each
    /// column's and each row's weights found once (a field integrated on a coarse grid brought
    /// back to the analysis grid costs a few nanoseconds a node).
    #[must_use]
    pub fn sampled_on(&self, cols: usize, rows: usize, spacing: f64) -> TensorField {
        use rayon::prelude::*;
        let weights = |n: usize, len: usize| -> Vec<(usize, usize, f32)> {
            (0..n)
                .map(|i| {
                    let (i0, i1, t) = axis_weights((i as f64 + 0.5) * spacing / self.spacing, len);
                    (i0, i1, t as f32)
                })
                .collect()
        };
        let across = weights(cols, self.cols);
        let down = weights(rows, self.rows);
        let mut data = vec![[0.0f32; 3]; cols * rows];
        data.par_chunks_mut(cols)
            .zip(&down)
            .for_each(|(row, &(r0, r1, ty))| {
                let (top, bottom) = (&self.data[r0 * self.cols..], &self.data[r1 * self.cols..]);
                for (out, &(c0, c1, tx)) in row.iter_mut().zip(&across) {
                    let (a, b, c, d) = (top[c0], top[c1], bottom[c0], bottom[c1]);
                    *out = std::array::from_fn(|k| {
                        let upper = a[k] + (b[k] - a[k]) * tx;
                        let lower = c[k] + (d[k] - c[k]) * tx;
                        upper + (lower - upper) * ty
                    });
                }
            });
        TensorField {
            cols,
            rows,
            spacing,
            domain: self.domain,
            data,
        }
    }

    /// The field box-averaged over blocks of `factor × factor` nodes (the last block of a row
    /// or column averages the nodes it has): the same domain on a grid `factor` times coarser.
    #[must_use]
    pub fn coarsened(&self, factor: usize) -> TensorField {
        use rayon::prelude::*;
        if factor <= 1 {
            return self.clone();
        }
        let (cols, rows) = (self.cols.div_ceil(factor), self.rows.div_ceil(factor));
        let mut data = vec![[0.0f32; 3]; cols * rows];
        data.par_chunks_mut(cols).enumerate().for_each(|(r, row)| {
            let (r0, r1) = (r * factor, ((r + 1) * factor).min(self.rows));
            for (c, out) in row.iter_mut().enumerate() {
                let (c0, c1) = (c * factor, ((c + 1) * factor).min(self.cols));
                let mut acc = [0.0f64; 3];
                for rr in r0..r1 {
                    for v in &self.data[rr * self.cols + c0..rr * self.cols + c1] {
                        for k in 0..3 {
                            acc[k] += f64::from(v[k]);
                        }
                    }
                }
                let n = ((r1 - r0) * (c1 - c0)) as f64;
                *out = acc.map(|a| (a / n) as f32);
            }
        });
        TensorField {
            cols,
            rows,
            spacing: self.spacing * factor as f64,
            domain: self.domain,
            data,
        }
    }

    /// The first node (column, row) in row-major order whose tensor is `bad`, searched in
    /// parallel over fixed chunks, each scanned in order (the answer is the first, whatever the
    /// thread count; rayon's `position_first` took 7.7 ms over a million nodes on two threads,
    /// this 1.5-1.9 ms).
    #[must_use]
    pub fn first_node_where(&self, bad: impl Fn(Tensor) -> bool + Sync) -> Option<(usize, usize)> {
        use rayon::prelude::*;
        const CHUNK: usize = 1 << 14;
        let firsts: Vec<Option<usize>> = self
            .data
            .par_chunks(CHUNK)
            .enumerate()
            .map(|(k, chunk)| {
                chunk
                    .iter()
                    .position(|&c| bad(Tensor::from_f32(c)))
                    .map(|i| k * CHUNK + i)
            })
            .collect();
        firsts
            .into_iter()
            .flatten()
            .next()
            .map(|i| (i % self.cols, i / self.cols))
    }
}

#[inline]
/// Lower node, upper node and weight of the upper node for a continuous grid coordinate
/// `u` (in node units, node `i` at `i + 0.5`), clamped to `[0, n − 1]`.
fn axis_weights(u: f64, n: usize) -> (usize, usize, f64) {
    let t = u - 0.5;
    // Grids have far fewer than 2³¹ nodes per axis, so the conversions go through i32, one
    // instruction each on baseline x86-64 (usize ↔ f64 takes several).
    let last = (n - 1) as i32;
    let t = if t.is_nan() {
        0.0
    } else {
        t.clamp(0.0, f64::from(last))
    };
    // t ≥ 0 here, so truncation is floor (and avoids a libm call).
    let i0 = (t as i32).min(last);
    let i1 = (i0 + 1).min(last);
    (i0 as usize, i1 as usize, t - f64::from(i0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn a_field_sampled_on_a_finer_grid_is_sample_at_every_node() {
        // An uneven field on a grid of spacing 3 over 70 × 50 pixels (the last nodes' blocks
        // partial), read onto grids of spacing 1 and 1.5.
        let data = (0..24 * 17)
            .map(|i| {
                let v = (i * 7919 % 1013) as f32 / 97.0;
                [v, 0.5 - v / 13.0, (v * 1.7).sin()]
            })
            .collect();
        let coarse = TensorField::with_spacing(24, 17, 3.0, (70.0, 50.0), data);
        for (cols, rows, spacing) in [(70, 50, 1.0), (47, 34, 1.5)] {
            let fine = coarse.sampled_on(cols, rows, spacing);
            assert_eq!(
                (fine.cols(), fine.rows(), fine.spacing()),
                (cols, rows, spacing)
            );
            assert_eq!(fine.domain(), coarse.domain());
            for r in 0..rows {
                for c in 0..cols {
                    let want = coarse.sample(fine.node_position(c, r)).to_f32();
                    let got = fine.data()[r * cols + c];
                    assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "{c},{r}");
                }
            }
        }
    }

    fn linear(p: DVec2) -> Tensor {
        Tensor::new(
            1.0 + 0.5 * p.x - 0.25 * p.y,
            0.125 * p.x + 0.5 * p.y,
            3.0 - p.x + 2.0 * p.y,
        )
    }

    proptest! {
        #[test]
        fn linear_field_is_reproduced(x in 0.5..62.5f64, y in 0.5..40.5f64) {
            let field = TensorField::from_fn(63, 41, linear);
            let got = field.sample(DVec2::new(x, y));
            let want = linear(DVec2::new(x, y));
            // f32 storage and blend: a few f32 ulps of the component magnitude.
            for (g, w) in [(got.xx, want.xx), (got.xy, want.xy), (got.yy, want.yy)] {
                prop_assert!((g - w).abs() <= 1e-5 * (1.0 + w.abs()), "{got:?} vs {want:?}");
            }
        }

        #[test]
        fn linear_field_with_spacing_is_reproduced(x in 2.0..60.0f64, y in 2.0..40.0f64) {
            let (cols, rows, s) = (16, 11, 4.0);
            let mut data = Vec::new();
            for r in 0..rows {
                for c in 0..cols {
                    data.push(linear(DVec2::new((c as f64 + 0.5) * s, (r as f64 + 0.5) * s)).to_f32());
                }
            }
            let field = TensorField::with_spacing(cols, rows, s, (64.0, 44.0), data);
            let got = field.sample(DVec2::new(x, y));
            let want = linear(DVec2::new(x, y));
            prop_assert!((got.xx - want.xx).abs() <= 1e-5 * (1.0 + want.xx.abs()));
            prop_assert!((got.yy - want.yy).abs() <= 1e-5 * (1.0 + want.yy.abs()));
        }
    }

    #[test]
    fn the_first_bad_node_is_the_first_in_row_order() {
        // 400 × 300 nodes: several parallel chunks; bad nodes in a late chunk and an early one.
        let (cols, rows) = (400, 300);
        let mut data = vec![[1.0f32, 0.0, 1.0]; cols * rows];
        for &(x, y) in &[(5usize, 250usize), (399, 60), (7, 60), (0, 61)] {
            data[y * cols + x] = [-1.0, 0.0, 1.0];
        }
        let field = TensorField::new(cols, rows, data);
        let bad = |t: Tensor| t.xx < 0.0;
        assert_eq!(field.first_node_where(bad), Some((7, 60)));
        let good = TensorField::new(cols, rows, vec![[1.0f32, 0.0, 1.0]; cols * rows]);
        assert_eq!(good.first_node_where(bad), None);
    }

    #[test]
    fn coarsening_keeps_a_linear_field() {
        let field = TensorField::from_fn(64, 48, linear);
        let coarse = field.coarsened(4);
        assert_eq!(
            (coarse.cols(), coarse.rows(), coarse.spacing()),
            (16, 12, 4.0)
        );
        assert_eq!(coarse.domain(), field.domain());
        // Block means of a linear field are its values at the block centres, which is where
        // the coarse nodes sit.
        for p in [
            DVec2::new(10.0, 10.0),
            DVec2::new(33.3, 21.7),
            DVec2::new(50.0, 40.0),
        ] {
            let (a, b) = (coarse.sample(p), linear(p));
            assert!(
                (a.xx - b.xx).abs() < 1e-4 && (a.yy - b.yy).abs() < 1e-4,
                "{a:?} {b:?}"
            );
        }
    }

    #[test]
    fn clamped_outside_and_nan_safe() {
        let field = TensorField::from_fn(4, 3, linear);
        assert_eq!(field.sample(DVec2::new(-10.0, -10.0)), field.node(0, 0));
        assert_eq!(field.sample(DVec2::new(100.0, 100.0)), field.node(3, 2));
        assert_eq!(field.sample(DVec2::new(f64::NAN, 0.0)), field.node(0, 0));
        let one = TensorField::constant(1, 1, Tensor::isotropic(2.0));
        assert_eq!(one.sample(DVec2::new(0.7, 0.2)), Tensor::isotropic(2.0));
    }
}
