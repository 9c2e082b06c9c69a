//! The model as a document: the model file and the share link in and out, and the exports of a patch
//! solid (SVG of its contours, HyperFun). Plain Rust over the core, tested natively; the page only
//! moves the strings and bytes.

use bezsolid_core::Solid2;
use bezsolid_core::contour::solid_contour;
use bezsolid_core::hyperfun::solid2_hf;
use bezsolid_core::link;
use bezsolid_core::mesh::svg::contours_svg;
use bezsolid_core::model::{ModelFile, ModelSolid};

/// The largest model file read (a degree-16 volume with long decimals is well under 1 MiB).
pub const MAX_MODEL_BYTES: usize = 16 << 20;
/// Cells per side of the exported contour (as `bezsolid contour`'s default).
pub const SVG_RESOLUTION: usize = 256;
/// How closely exported contour vertices lie on f = 0.
pub const SVG_ACCURACY: f64 = 1e-9;

/// The model file of a patch solid, as pretty JSON.
#[must_use]
pub fn model_json(solid: &Solid2) -> String {
    let file = ModelFile::from_solid2(solid);
    // Serialising plain numbers and strings into a String cannot fail.
    serde_json::to_string_pretty(&file).unwrap_or_default() + "\n"
}

fn patch_only(model: ModelSolid) -> Result<Solid2, String> {
    match model {
        ModelSolid::Patch(s) => Ok(s),
        ModelSolid::Volume(_) => Err(
            "this is a volume (3D) model; the page edits patch (2D) models so far: use `bezsolid mesh` \
             or `bezsolid hf` on it"
                .into(),
        ),
    }
}

/// The patch preset called `name`.
///
/// # Errors
///
/// For an unknown name or a volume preset.
pub fn open_preset(name: &str) -> Result<Solid2, String> {
    let preset = bezsolid_core::presets::Preset::from_name(name)
        .ok_or_else(|| format!("no preset {name:?}"))?;
    patch_only(preset.solid())
}

/// Reads a model file's text.
///
/// # Errors
///
/// A message that says what is wrong: too large, not JSON, not a model, or an invalid net.
pub fn read_model(text: &str) -> Result<Solid2, String> {
    if text.len() > MAX_MODEL_BYTES {
        return Err(format!(
            "the file is {} bytes; a model file is at most {MAX_MODEL_BYTES}",
            text.len()
        ));
    }
    let file: ModelFile =
        serde_json::from_str(text).map_err(|e| format!("not a bezsolid model file: {e}"))?;
    patch_only(file.to_solid().map_err(|e| e.to_string())?)
}

/// The share link fragment `#v1.…` of a patch solid.
///
/// # Errors
///
/// When the model is too large for a link.
pub fn share_fragment(solid: &Solid2) -> Result<String, String> {
    link::encode(&ModelFile::from_solid2(solid)).map_err(|e| e.to_string())
}

/// The solid of a share link (a whole URL or its fragment).
///
/// # Errors
///
/// A message that says what is wrong with the link.
pub fn open_link(text: &str) -> Result<Solid2, String> {
    patch_only(link::decode(text).map_err(|e| e.to_string())?)
}

/// The zero contours as SVG, in the domain's box with a one-cell margin.
#[must_use]
pub fn svg(solid: &Solid2) -> String {
    let (lo, hi) = solid.domain();
    let cell = (hi - lo) / SVG_RESOLUTION as f64;
    contours_svg(
        &solid_contour(solid, SVG_RESOLUTION, SVG_ACCURACY),
        lo - cell,
        hi + cell,
    )
}

/// The HyperFun model.
///
/// # Errors
///
/// For a space-mapped model, which HyperFun cannot express.
pub fn hyperfun(solid: &Solid2) -> Result<String, String> {
    solid2_hf(solid).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn moved() -> Solid2 {
        let mut s = Solid2::fig9();
        s.set_point(1, 2, DVec2::new(0.61, 1.2)).unwrap();
        s.set_xi(0, 1, 0.123_456_789_012_345_6).unwrap();
        s
    }

    #[test]
    fn model_file_and_link_round_trip_exactly() {
        let s = moved();
        assert_eq!(read_model(&model_json(&s)), Ok(s.clone()));
        let link = share_fragment(&s).unwrap();
        assert_eq!(open_link(&format!("http://h/{link}")), Ok(s));
    }

    #[test]
    fn bad_files_and_links_say_what_is_wrong() {
        assert!(
            read_model("{")
                .unwrap_err()
                .contains("not a bezsolid model file")
        );
        assert!(read_model(r#"{"format":"bezsolid","version":9,"solid":{"kind":"patch","degree":[1,1],"points":[]}}"#)
            .unwrap_err()
            .contains("version 9"));
        let volume = bezsolid_core::presets::Preset::from_name("blob")
            .unwrap()
            .solid();
        let ModelSolid::Volume(v) = volume else {
            unreachable!()
        };
        let text = serde_json::to_string(&ModelFile::from_solid3(&v)).unwrap();
        assert!(read_model(&text).unwrap_err().contains("volume"));
        assert!(open_link("#v1.AAAA").unwrap_err().contains("damaged"));
        assert!(
            read_model(&" ".repeat(MAX_MODEL_BYTES + 1))
                .unwrap_err()
                .contains("at most")
        );
    }

    #[test]
    fn exports_hold_the_model() {
        let s = moved();
        let svg = svg(&s);
        assert!(
            svg.starts_with("<?xml") || svg.starts_with("<svg"),
            "{}",
            &svg[..40]
        );
        assert!(svg.contains("<path") || svg.contains("<polyline") || svg.contains("<polygon"));
        assert!(hyperfun(&s).unwrap_err().contains("regular grid"));
        assert!(hyperfun(&Solid2::fig9()).unwrap().contains("my_model("));
    }
}
