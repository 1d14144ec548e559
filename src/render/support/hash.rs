//! Deterministic per-site randomness: every random choice a look makes about a cell (or a
//! pixel) is a hash of the site's index and a salt of its own, so the same input and seed give
//! the same picture at any thread count, and no two choices are correlated.

/// Salts of [`site_hash`]: every per-cell (or per-pixel) random choice of the looks has its
/// own, so that two choices about one cell are independent and no look's pattern repeats
/// another's. The values are arbitrary but fixed: changing one changes the pictures.
pub mod salt {
    /// Stipple dot position inside its grid cell (x and y) and its order among its
    /// neighbours (which lies above), cut from one word.
    pub const STIPPLE: u64 = 2;
    /// Phase of a stroke texture's bristle streaks along the cell.
    pub const STROKE_PHASE: u64 = 4;
    /// Brightness of one bristle streak of a stroke texture.
    pub const STROKE_BRISTLE: u64 = 5;
    /// Brightness of one bristle of a brush glyph.
    pub const GLYPH_BRISTLE: u64 = 6;
    /// Brightness change of a mosaic cell (`look.jitter`).
    pub const MOSAIC_JITTER: u64 = 7;
    /// The white noise of the LIC look, per pixel.
    pub const LIC_NOISE: u64 = 11;
    /// Brightness of a fabric thread dot; the axis (0 or 1) is added.
    pub const FABRIC_THREAD: u64 = 12;
    /// Lightness, red, green and blue of a pointillist dot (16 bits each of one word).
    pub const DOT_COLOUR: u64 = 16;
    /// The turn of a brush stroke in a flat area from the flat angle.
    pub const FLAT_STROKE: u64 = 17;
}

/// Knuth's multiplicative hash constant (2³² / φ): spreads consecutive integers over `u32`
/// before they are combined with a site index.
pub const GOLDEN_U32: u32 = 2_654_435_761;

/// A small deterministic hash of a site index to [0, 1) (SplitMix64 finaliser).
#[inline]
#[must_use]
pub fn site_hash(site: u32, salt: u64) -> f32 {
    // The top 24 bits, exact in an f32. Through `u32`: on x86-64 a `u64` becomes a float in a
    // branchy sequence, a `u32` in one instruction (dot centres hash twice per lattice cell
    // at every stippled pixel).
    (site_bits(site, salt) >> 40) as u32 as f32 / (1u32 << 24) as f32
}

/// The 64 bits [`site_hash`] takes its top 24 from: per-pixel code that needs several
/// independent values (a pointillist dab's four) cuts them from one word.
#[inline]
#[must_use]
pub fn site_bits(site: u32, salt: u64) -> u64 {
    let mut z = u64::from(site)
        .wrapping_add(salt.wrapping_mul(0x9E37_79B9_7F4A_7C15))
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_is_spread() {
        let mean: f32 = (0..10_000).map(|i| site_hash(i, 3)).sum::<f32>() / 10_000.0;
        assert!((mean - 0.5).abs() < 0.02);
        assert_ne!(site_hash(1, 0), site_hash(1, 1));
    }
}
