//! Style presets describe a painting; they run nothing. A preset is a TOML file holding every
//! parameter of the chain (metric, sampler, cells, outlines, highlights, look): [`schema`]
//! declares every key once (what it takes, which looks read it, what it does), [`preset`]
//! loads a preset and checks it against the schema (built-ins compiled in from `styles/`,
//! `extends` chains, `--set key.path=value` overrides, errors with file, line and column and
//! the nearest key), [`convert`] turns its keys into the library's parameter structs and the
//! [`Look`](crate::render::Look), [`full`] writes a preset out with every key it paints with,
//! [`sheet`] lists the variants of a contact sheet. Lengths in `[metric]` are fractions of the
//! image diagonal, as in [`MetricParams`](crate::field::MetricParams).
//! [`crate::paint`](mod@crate::paint) runs the chain a preset describes.

pub mod convert;
pub mod full;
pub mod preset;
pub mod schema;
pub mod sheet;

pub use full::{full_toml, key_values};
pub use preset::{
    apply_sets, built_in, load, merge, parse, CellsSection, HighlightsSection, LookSection,
    MetricSection, OutlinesSection, Preset, PresetFile, SamplerSection, BUILT_IN,
    BUILT_IN_TEXTURES, DEFAULT_STYLE,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::looks::texture::TextureKind;
    use crate::render::Look;
    use std::path::Path;

    #[test]
    fn textures_come_from_beside_the_preset_or_the_built_in_ones() {
        let dir = tempfile::tempdir().unwrap();
        let own = dir.path().join("mine.toml");
        std::fs::write(
            &own,
            "[look]\nkind = \"hatch\"\ntexture = \"engraving.png\"\n",
        )
        .unwrap();
        let look = load(own.to_str().unwrap()).unwrap().look().unwrap();
        let Look::Texture(p) = look else {
            panic!("a hatch is a textured look")
        };
        assert_eq!(
            p.kind,
            TextureKind::Image(crate::render::looks::texture::engraving_tile(64))
        );
        // A tile beside the preset wins over the built-in one of the same name.
        let tile = image::GrayImage::from_pixel(8, 8, image::Luma([7]));
        tile.save(dir.path().join("engraving.png")).unwrap();
        let Look::Texture(p) = load(own.to_str().unwrap()).unwrap().look().unwrap() else {
            panic!("textured")
        };
        assert_eq!(p.kind, TextureKind::Image(tile));
        std::fs::write(&own, "[look]\nkind = \"hatch\"\ntexture = \"nope.png\"\n").unwrap();
        let err = load(own.to_str().unwrap())
            .unwrap()
            .look()
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("nope.png") && err.contains("engraving.png"),
            "{err}"
        );
    }

    #[test]
    fn built_in_textures_are_the_ones_the_project_makes() {
        // REGENERATE=1 rewrites the file from its generator.
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("styles/textures/engraving.png");
        let made = crate::render::looks::texture::engraving_tile(64);
        if std::env::var_os("REGENERATE").is_some() {
            made.save(&path).unwrap();
        }
        let committed = image::open(&path).unwrap().to_luma8();
        assert_eq!(committed, made, "styles/textures/engraving.png is stale");
        let (_, bytes) = BUILT_IN_TEXTURES[0];
        assert_eq!(image::load_from_memory(bytes).unwrap().to_luma8(), made);
    }

    #[test]
    fn every_built_in_preset_loads_and_builds() {
        for (name, _) in BUILT_IN {
            let p = load(name).unwrap();
            assert!(p.file.description.is_some(), "{name} has no description");
            p.metric().unwrap();
            p.look().unwrap();
        }
    }

    #[test]
    fn unknown_keys_and_wrong_types_name_line_column_and_valid_keys() {
        let e = parse("[look]\nkind = \"mosaic\"\nborder_widht = 2\n", "x.toml").unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("x.toml:3:1"), "{msg}");
        assert!(msg.contains("did you mean look.border_width?"), "{msg}");
        // A key of another look, in a file: the looks that read it and the nearest key.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mine.toml");
        std::fs::write(&path, "[look]\nkind = \"mosaic\"\nlines_per_cell = 5\n").unwrap();
        let msg = load(path.to_str().unwrap()).unwrap_err().to_string();
        assert!(
            msg.contains("look.lines_per_cell is not read by the mosaic look"),
            "{msg}"
        );
        assert!(msg.contains("the mosaic look reads look.kind"), "{msg}");
        // A key of an earlier layout says where it went, in a file and through --set.
        let e = parse("[look]\nkind = \"hatch\"\noutlines = 1.0\n", "old.toml").unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("old.toml:3:1"), "{msg}");
        assert!(
            msg.contains(
                "look.outlines is now outlines.strength: write `strength = …` under [outlines]"
            ),
            "{msg}"
        );
        let mut p = load("mosaic").unwrap();
        let e = apply_sets(&mut p, &["look.cells=voronoi".into()]).unwrap_err();
        assert!(
            e.to_string().contains("look.cells is now cells.kind"),
            "{e}"
        );
        let e = parse("[metric]\nmax_anisotropy = \"lots\"\n", "y.toml").unwrap_err();
        assert!(e.to_string().contains("y.toml:2:18"), "{e}");
    }

    #[test]
    fn extends_and_set_override_the_base() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mine.toml");
        std::fs::write(&path, "extends = \"mosaic\"\n[look]\nborder_width = 4.0\n").unwrap();
        let mut p = load(path.to_str().unwrap()).unwrap();
        let base = load("mosaic").unwrap();
        assert_eq!(p.file.look.kind, base.file.look.kind);
        assert_eq!(p.file.look.border_width, Some(4.0));
        apply_sets(
            &mut p,
            &["metric.max_anisotropy=6".into(), "look.relief=0.5".into()],
        )
        .unwrap();
        assert_eq!(p.metric().unwrap().max_anisotropy, 6.0);
        assert_eq!(p.file.look.relief, Some(0.5));
        // A key another look reads is an error naming the looks that read it.
        let e = apply_sets(&mut p, &["look.ink=pixel".into()]).unwrap_err();
        assert!(
            e.to_string()
                .contains("not read by the mosaic look (only by hatch"),
            "{e}"
        );
        // Switching look leaves the old look's keys behind.
        apply_sets(&mut p, &["look.kind=hatch".into(), "look.ink=pixel".into()]).unwrap();
        assert_eq!(p.file.look.relief, None);
        assert_eq!(p.file.look.ink.as_deref(), Some("pixel"));
        assert!(apply_sets(&mut p, &["look.nope=1".into()]).is_err());
        assert!(apply_sets(&mut p, &["nodot=1".into()]).is_err());
    }
}
