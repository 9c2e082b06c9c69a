//! The page's free-form work without a page (the worker's jobs, and node).

use super::read_file;
use crate::error::Error;
use bezsolid_core::mesh::exchange::ExportFormat;

/// Why the mesh of a result that holds everything far from its solids is refused.
pub const UNBOUNDED: &str = "the result is unbounded (a complement holds everything outside \
     its solids): intersect it with a bounded solid to mesh it";

/// The largest resolution of a headless surface or mesh.
pub const MAX_RESOLUTION: usize = bezsolid_core::esc::draw::MAX_RESOLUTION;

fn boolean(text: &str, resolution: usize) -> Result<bezsolid_core::esc::Boolean, Error> {
    if !(2..=MAX_RESOLUTION).contains(&resolution) {
        return Err(Error::new(format!(
            "resolution {resolution} is outside 2..={MAX_RESOLUTION}"
        )));
    }
    read_file(text)?.to_boolean().map_err(Error::from)
}

/// The result's surface of a free-form model or link, as [`super::surface_floats`].
///
/// # Errors
///
/// What is wrong with the input or the resolution (2 to 160).
pub fn surface(text: &str, resolution: usize) -> Result<Vec<f32>, Error> {
    Ok(super::surface_floats(
        &boolean(text, resolution)?,
        resolution,
    ))
}

/// A mesh file of the result's surface.
///
/// # Errors
///
/// As [`surface`], or an empty result.
pub fn mesh(text: &str, format: ExportFormat, resolution: usize) -> Result<Vec<u8>, Error> {
    mesh_in_steps(text, format, resolution, |_, _| {})
}

/// [`mesh`], calling `progress(done, total)` after each layer of the result's samples and at
/// the end ([`bezsolid_core::esc::Boolean::surface_in_steps`]).
///
/// # Errors
///
/// As [`mesh`].
pub fn mesh_in_steps(
    text: &str,
    format: ExportFormat,
    resolution: usize,
    progress: impl FnMut(usize, usize),
) -> Result<Vec<u8>, Error> {
    Ok(format.write(
        &result_mesh(text, resolution, progress)?,
        crate::document::headless::TITLE,
    )?)
}

/// The closed mesh of the result's surface that [`mesh_in_steps`] writes.
///
/// # Errors
///
/// As [`mesh`].
pub fn result_mesh(
    text: &str,
    resolution: usize,
    progress: impl FnMut(usize, usize),
) -> Result<bezsolid_core::mesh::Mesh, Error> {
    let boolean = boolean(text, resolution)?;
    if !boolean.is_bounded() {
        return Err(UNBOUNDED.into());
    }
    let mesh = boolean.surface_in_steps(resolution, progress);
    if mesh.triangles.is_empty() {
        return Err("the result is empty: there is no surface to export".into());
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use crate::freeform::{FreeForm, headless, is_free_form};
    use bezsolid_core::mesh::exchange::ExportFormat;

    #[test]
    fn headless_surfaces_and_meshes_of_files_and_links() {
        let f = FreeForm::new();
        let json = serde_json::to_string(&f.model_file()).unwrap();
        let link = bezsolid_core::link::encode(&f.model_file()).unwrap();
        assert!(is_free_form(&json) && is_free_form(&link));
        assert!(!is_free_form("{}"));
        let a = headless::surface(&json, 16).unwrap();
        assert_eq!(a, headless::surface(&link, 16).unwrap());
        assert!(a.len() > 18 * 100);
        // The export is the closed mesh of the same resolution.
        let stl = headless::mesh(&link, ExportFormat::Stl, 16).unwrap();
        let closed = f.boolean().surface(16);
        closed.check_closed_manifold().unwrap();
        assert_eq!(stl.len(), 84 + 50 * closed.triangles.len());
        assert!(headless::mesh(&link, ExportFormat::Stl, 1000).is_err());
        assert!(headless::surface(&link, 1000).is_err());
        // A complement holds everything far away: no mesh, whichever way it is asked for.
        let complement = r#"{ "format": "bezsolid", "version": 1,
            "solid": { "kind": "esc", "operation": "complement",
                       "operands": [ { "example": "icosphere" } ] } }"#;
        for e in [
            headless::mesh(complement, ExportFormat::Stl, 16).unwrap_err(),
            headless::result_mesh(complement, 16, |_, _| {}).unwrap_err(),
        ] {
            assert_eq!(e.message(), headless::UNBOUNDED);
        }
        assert!(headless::surface("#v1.garbage", 16).is_err());
    }
}
