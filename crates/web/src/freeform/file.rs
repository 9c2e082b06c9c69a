//! Free-form model files: reading one (JSON or a share link), writing one, and telling one apart.

use bezsolid_core::model::{ModelFile, SolidSpec};

use crate::error::Error;

/// The model file in `text`: JSON, or a share link (a whole URL or its fragment).
///
/// # Errors
///
/// What is wrong with it.
pub fn read_file(text: &str) -> Result<ModelFile, Error> {
    if text.len() > crate::document::MAX_MODEL_BYTES {
        return Err(Error::new(format!(
            "the file is {} bytes; a model file is at most {}",
            text.len(),
            crate::document::MAX_MODEL_BYTES
        )));
    }
    if text.trim_start().starts_with('{') {
        serde_json::from_str(text)
            .map_err(|e| Error::new(format!("not a bezsolid model file: {e}")))
    } else {
        bezsolid_core::link::decode_file(text).map_err(Error::from)
    }
}

/// The text of a free-form model file: indented, or compact when an operand is a mesh.
#[must_use]
pub fn model_json(file: &ModelFile) -> String {
    let has_mesh = matches!(&file.solid, SolidSpec::Esc { operands, .. }
        if operands.iter().any(|o| o.mesh.is_some()));
    if has_mesh {
        serde_json::to_string(file)
    } else {
        serde_json::to_string_pretty(file)
    }
    .unwrap_or_default()
}

/// Whether `text` (a model file or link) holds a free-form model.
#[must_use]
pub fn is_free_form(text: &str) -> bool {
    read_file(text).is_ok_and(|f| matches!(f.solid, SolidSpec::Esc { .. }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::freeform::FreeForm;

    #[test]
    fn model_files_with_meshes_are_compact_and_read_back() {
        let mut f = FreeForm::new();
        assert!(model_json(&f.model_file()).contains('\n'));
        f.set_mesh(1, "ball.obj", &bezsolid_core::esc::examples::icosphere(2))
            .unwrap();
        let text = model_json(&f.model_file());
        assert!(!text.contains('\n'));
        assert_eq!(read_file(&text).unwrap(), f.model_file());
    }
}
