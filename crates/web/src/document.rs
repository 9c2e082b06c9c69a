//! The model as a document: the model file and the share link in and out, and the exports (SVG of
//! the patch's or the selected slice's contours, HyperFun, and for volumes STL, OBJ and PLY meshes).
//! Plain Rust over the core, tested natively; the page only moves the strings and bytes.

use bezsolid_core::contour::solid_contour;
use bezsolid_core::link;
use bezsolid_core::mesh::Mesh;
use bezsolid_core::mesh::svg::contours_svg;
use bezsolid_core::model::{ModelFile, ModelSolid, SolidSpec};
use bezsolid_core::{Solid2, SolidError};

use crate::editor::{Cells, Editor, MAX_PIECEWISE_POINTS, piecewise_spec};
use crate::error::Error;

/// Accuracy of exported mesh vertices on f = 0.
pub const MESH_ACCURACY: f64 = 1e-9;

/// The largest model file read (a degree-16 volume with long decimals is well under 1 MiB).
pub const MAX_MODEL_BYTES: usize = 16 << 20;
/// Cells per side of the exported contour (as `bezsolid contour`'s default).
pub const SVG_RESOLUTION: usize = 256;
/// How closely exported contour vertices lie on f = 0.
pub const SVG_ACCURACY: f64 = 1e-9;

/// The model file of the editor's model (a piecewise one as its cells and global net).
#[must_use]
pub fn model_file(editor: &Editor) -> ModelFile {
    let plain = match editor.volume() {
        Some(v) => ModelFile::from_solid3(v),
        None => ModelFile::from_solid2(editor.solid()),
    };
    ModelFile::from_spec(piecewise_spec(editor.cells(), plain.solid))
}

/// The model file of the editor's model, as pretty JSON.
#[must_use]
pub fn model_json(editor: &Editor) -> String {
    // Serialising plain numbers and strings into a String cannot fail.
    serde_json::to_string_pretty(&model_file(editor)).unwrap_or_default() + "\n"
}

/// Opens `model` in the editor (one undo step).
pub fn open(editor: &mut Editor, model: ModelSolid) {
    match model {
        ModelSolid::Patch(s) => editor.set_solid(s),
        ModelSolid::Volume(v) => editor.set_volume(v),
    }
}

/// Whether the editor edits `spec` as a node of a model: a patch, a volume, or a piecewise one
/// whose global net has at most [`MAX_PIECEWISE_POINTS`] points along each axis.
#[must_use]
pub fn editable(spec: &SolidSpec) -> bool {
    match spec {
        SolidSpec::Patch { .. } | SolidSpec::Volume { .. } => true,
        SolidSpec::Piecewise { cells, degree, .. } => cells
            .iter()
            .zip(degree)
            .all(|(&c, &d)| c.saturating_mul(d) < MAX_PIECEWISE_POINTS),
        _ => false,
    }
}

/// Opens a node of a model in the editor (one undo step): a patch or a volume, or a piecewise
/// one, whose global net the editor edits as one net.
///
/// # Errors
///
/// What is wrong with the node, or that the editor does not edit it ([`editable`]); the
/// editor is unchanged then.
pub fn open_spec(editor: &mut Editor, spec: SolidSpec) -> Result<(), Error> {
    let SolidSpec::Piecewise { cells, degree, .. } = &spec else {
        open(editor, ModelFile::from_spec(spec).to_solid()?);
        return Ok(());
    };
    if !editable(&spec) {
        return Err(Error::new(format!(
            "this piecewise net has more than {MAX_PIECEWISE_POINTS} points along an axis: it is \
             drawn, saved and exported as it is, and edited as a file"
        )));
    }
    let cells = Cells {
        count: cells.clone(),
        degree: degree.clone(),
    };
    let net = match cells.count.len() {
        2 => ModelSolid::Patch(global_net::<2>(&spec)?),
        _ => ModelSolid::Volume(global_net::<3>(&spec)?),
    };
    editor.set_piecewise(net, cells)
}

/// The global net of a piecewise spec as one solid's net (checked as a piecewise solid first,
/// for its errors).
fn global_net<const D: usize>(spec: &SolidSpec) -> Result<bezsolid_core::Solid<D>, Error>
where
    bezsolid_core::Dim<D>: bezsolid_core::Dimension<D>,
{
    let solid = spec
        .to_piecewise::<D>()
        .ok_or_else(|| Error::new(format!("not a piecewise solid of {D} axes")))?
        .map_err(|e| Error::new(e.to_string()))?;
    let net = bezsolid_core::Tensor::try_new(solid.dims().map(|n| n - 1), solid.points().to_vec())
        .map_err(SolidError::from)?;
    Ok(bezsolid_core::Solid::try_from_net(net)?)
}

/// The preset called `name`.
///
/// # Errors
///
/// For an unknown name.
pub fn preset(name: &str) -> Result<ModelSolid, Error> {
    bezsolid_core::presets::Preset::from_name(name)
        .map(bezsolid_core::presets::Preset::solid)
        .ok_or_else(|| Error::new(format!("no preset {name:?}")))
}

/// Reads a model file's text.
///
/// # Errors
///
/// A message that says what is wrong: too large, not JSON, not a model, or an invalid net.
pub fn read_model(text: &str) -> Result<ModelSolid, Error> {
    if text.len() > MAX_MODEL_BYTES {
        return Err(Error::new(format!(
            "the file is {} bytes; a model file is at most {MAX_MODEL_BYTES}",
            text.len()
        )));
    }
    let file: ModelFile = serde_json::from_str(text)
        .map_err(|e| Error::new(format!("not a bezsolid model file: {e}")))?;
    file.to_solid().map_err(Error::from)
}

/// The model file of a model file's text or a share link, checked as far as its header and
/// shape (not yet built).
///
/// # Errors
///
/// Too large, not JSON, not a model, or a damaged link.
pub fn read_file(text: &str) -> Result<ModelFile, Error> {
    if !text.trim_start().starts_with('{') {
        return link::decode_file(text).map_err(Error::from);
    }
    if text.len() > MAX_MODEL_BYTES {
        return Err(Error::new(format!(
            "the file is {} bytes; a model file is at most {MAX_MODEL_BYTES}",
            text.len()
        )));
    }
    serde_json::from_str(text).map_err(|e| Error::new(format!("not a bezsolid model file: {e}")))
}

/// The share link fragment `#v1.…` of the editor's model.
///
/// # Errors
///
/// When the model is too large for a link.
pub fn share_fragment(editor: &Editor) -> Result<String, Error> {
    link::encode(&model_file(editor)).map_err(Error::from)
}

/// The solid of a share link (a whole URL or its fragment).
///
/// # Errors
///
/// A message that says what is wrong with the link.
pub fn open_link(text: &str) -> Result<ModelSolid, Error> {
    link::decode(text).map_err(Error::from)
}

/// The model file (JSON) of the patch the 2D view edits: the model itself, or the selected slice
/// of a volume (what [`svg`] draws).
#[must_use]
pub fn patch_json(editor: &Editor) -> String {
    let file = match editor.piecewise2() {
        Some(p) => ModelFile::from_spec(SolidSpec::from_piecewise(&p)),
        None => ModelFile::from_solid2(editor.solid()),
    };
    serde_json::to_string(&file).unwrap_or_default()
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

/// A model from text that is either a model file (JSON) or a share link (a URL or a fragment).
///
/// # Errors
///
/// What is wrong with the file or the link.
pub fn read_any(text: &str) -> Result<ModelSolid, Error> {
    if text.trim_start().starts_with('{') {
        read_model(text)
    } else {
        open_link(text)
    }
}

/// The page's module without a page: a model file or a link in, the model file, the link or a mesh
/// file out (for node and other headless hosts).
pub mod headless {
    use super::{Editor, MESH_ACCURACY, model_json, open, read_any, read_file, share_fragment};
    use crate::error::Error;
    use bezsolid_core::contour::solid_contour;
    use bezsolid_core::mesh::exchange::ExportFormat;
    use bezsolid_core::mesh::{Mesh, Share};
    use bezsolid_core::model::ModelSolid;
    use bezsolid_core::tree::{MeshCache, ModelTree, Tree, TreeMeshError};
    use bezsolid_core::{Axis, Solid2};

    /// The tree of a model of many solids, or `None` for a model of one solid.
    fn tree(text: &str) -> Result<Option<ModelTree>, Error> {
        let file = read_file(text)?;
        if !file.solid.is_tree() {
            return Ok(None);
        }
        Ok(Some(file.to_tree()?))
    }

    /// The closed mesh of a 3D tree at `resolution` (within its bounds). With `view`, a tree
    /// that may be unbounded is meshed cut by a box a quarter larger on every side than its
    /// bounded parts ([`bezsolid_core::tree::Tree::parts_box`]): what the 3D view shows of it.
    fn tree_mesh(
        tree: &ModelTree,
        resolution: usize,
        view: bool,
        progress: impl FnMut(usize, usize),
    ) -> Result<Mesh, Error> {
        let (space, region) = tree_space(tree, resolution, view)?;
        space
            .polygonize_in_steps(resolution, MESH_ACCURACY, region, progress)
            .map(|(mesh, _)| mesh)
            .map_err(unbounded)
    }

    /// A box, `[min, max]`.
    type Box3 = ([f64; 3], [f64; 3]);

    /// The 3D tree of `tree` and the box [`tree_mesh`] meshes it in (`None`: its bounds).
    fn tree_space(
        tree: &ModelTree,
        resolution: usize,
        view: bool,
    ) -> Result<(&Tree<3>, Option<Box3>), Error> {
        if !(2..=MAX_RESOLUTION).contains(&resolution) {
            return Err(Error::new(format!(
                "resolution {resolution} is outside 2..={MAX_RESOLUTION}"
            )));
        }
        match tree {
            ModelTree::Space(t) if view && t.bounds().is_none() => {
                let (lo, hi) = t.parts_box().unwrap_or(([-1.0; 3], [1.0; 3]));
                let grow = (0..3).map(|i| hi[i] - lo[i]).fold(1e-3, f64::max) * 0.25;
                Ok((t, Some((lo.map(|x| x - grow), hi.map(|x| x + grow)))))
            }
            ModelTree::Space(t) => Ok((t, None)),
            ModelTree::Plane(_) => {
                Err("meshes are of 3D models; this is a 2D model: export its contour".into())
            }
        }
    }

    fn unbounded(e: TreeMeshError) -> Error {
        match e {
            TreeMeshError::Unbounded => Error::new(
                "the model may be unbounded (a half-space, a cylinder, a morph past 0..1 or a \
                 blend of a space-mapped solid): intersect it with a box, or mesh it with \
                 `bezsolid mesh --box`",
            ),
            other => other.into(),
        }
    }

    /// The name a mesh file gives its model (3MF's title, the GLB's mesh).
    pub const TITLE: &str = "bezsolid";

    /// The largest resolution a headless mesh is made at.
    pub const MAX_RESOLUTION: usize = 512;

    /// What a headless job made, and how many evaluations of `f` in it ran out of their work
    /// budget (where a net folds over itself very many times): where they did, `data` is
    /// approximate.
    #[derive(Debug)]
    pub struct Made<T> {
        /// The file, surface or stack.
        pub data: T,
        /// Evaluations that ran out of their work budget; 0 where `data` is exact.
        pub approximate: usize,
    }

    fn volume(text: &str, resolution: usize) -> Result<bezsolid_core::Solid3, Error> {
        if !(2..=MAX_RESOLUTION).contains(&resolution) {
            return Err(Error::new(format!(
                "resolution {resolution} is outside 2..={MAX_RESOLUTION}"
            )));
        }
        match read_any(text)? {
            ModelSolid::Volume(v) => Ok(v),
            ModelSolid::Patch(_) => Err("meshes are of volume (3D) models; this is a patch".into()),
        }
    }

    fn editor(text: &str) -> Result<Editor, Error> {
        let mut e = Editor::new(Solid2::fig9());
        open(&mut e, read_any(text)?);
        e.forget_history();
        Ok(e)
    }

    /// The model file (JSON) of a model file or link.
    ///
    /// # Errors
    ///
    /// What is wrong with the input.
    pub fn model(text: &str) -> Result<String, Error> {
        if tree(text)?.is_some() {
            let file = read_file(text)?;
            return Ok(serde_json::to_string_pretty(&file).unwrap_or_default() + "\n");
        }
        editor(text).map(|e| model_json(&e))
    }

    /// The share link fragment of a model file or link.
    ///
    /// # Errors
    ///
    /// What is wrong with the input, or a model too large for a link.
    pub fn link(text: &str) -> Result<String, Error> {
        if tree(text)?.is_some() {
            return Ok(bezsolid_core::link::encode(&read_file(text)?)?);
        }
        share_fragment(&editor(text)?)
    }

    /// A mesh file of a volume model at `resolution` cells along the longest side.
    ///
    /// # Errors
    ///
    /// What is wrong with the input, a patch model, or a resolution outside 2 to 512.
    pub fn mesh(
        text: &str,
        format: ExportFormat,
        resolution: usize,
    ) -> Result<Made<Vec<u8>>, Error> {
        mesh_in_steps(text, format, resolution, |_, _| {})
    }

    /// [`mesh`], calling `progress(done, total)` on the way and at the end (`done == total`).
    ///
    /// # Errors
    ///
    /// As [`mesh`].
    pub fn mesh_in_steps(
        text: &str,
        format: ExportFormat,
        resolution: usize,
        progress: impl FnMut(usize, usize),
    ) -> Result<Made<Vec<u8>>, Error> {
        if let Some(t) = tree(text)? {
            return Ok(Made {
                data: format.write(&tree_mesh(&t, resolution, false, progress)?, TITLE)?,
                approximate: 0,
            });
        }
        let v = volume(text, resolution)?;
        let m = v
            .polygonize_in_steps(resolution, MESH_ACCURACY, progress)
            .map_err(Error::from)?;
        Ok(Made {
            data: format.write(&m, TITLE)?,
            approximate: v.exhausted(),
        })
    }

    /// The surface the page draws for a volume model at `resolution`, as six `f32` per vertex
    /// (position, normal), three vertices per triangle: what the page's worker computes.
    ///
    /// # Errors
    ///
    /// As [`mesh`].
    pub fn surface(text: &str, resolution: usize) -> Result<Made<Vec<f32>>, Error> {
        if let Some(t) = tree(text)? {
            return Ok(Made {
                data: crate::view3d::mesh_floats(&tree_mesh(&t, resolution, true, |_, _| {})?),
                approximate: 0,
            });
        }
        let v = volume(text, resolution)?;
        Ok(Made {
            data: crate::view3d::surface_floats(&v, resolution),
            approximate: v.exhausted(),
        })
    }

    std::thread_local! {
        /// The pieces of the last tree surface this thread made a share of, block by block.
        static SURFACES: core::cell::RefCell<MeshCache> = core::cell::RefCell::new(MeshCache::new());
    }

    /// The share `share` of the surface [`surface`] makes, for a page that makes it in several
    /// workers: the shares' floats, one after another, are that surface's floats. A model of
    /// many solids whose bounds an edit left as they were is meshed again only near what changed
    /// since this thread's last share of it ([`bezsolid_core::tree::MeshCache`]).
    ///
    /// # Errors
    ///
    /// As [`surface`].
    pub fn surface_share(
        text: &str,
        resolution: usize,
        share: Share,
    ) -> Result<Made<Vec<f32>>, Error> {
        surface_share_kept(text, resolution, share).map(|(made, _)| made)
    }

    /// `[kept, blocks]`: the blocks of a share of a surface taken from the last mesh, of all.
    pub type KeptBlocks = [usize; 2];

    /// [`surface_share`], with `[kept, blocks]` for a model of many solids: the blocks of the
    /// share taken from this thread's last mesh of the model, of all it meshed.
    ///
    /// # Errors
    ///
    /// As [`surface`].
    pub fn surface_share_kept(
        text: &str,
        resolution: usize,
        share: Share,
    ) -> Result<(Made<Vec<f32>>, Option<KeptBlocks>), Error> {
        if let Some(t) = tree(text)? {
            let (space, region) = tree_space(&t, resolution, true)?;
            // The blocks an edit since the last share of this thread cannot have changed are
            // taken from the cache (a worker is given the same share each time).
            let (piece, made) = SURFACES
                .with_borrow_mut(|cache| {
                    space.polygonize_share_cached(resolution, MESH_ACCURACY, region, share, cache)
                })
                .map_err(unbounded)?;
            return Ok((
                Made {
                    data: crate::view3d::mesh_floats(&piece.mesh),
                    approximate: 0,
                },
                Some([made.kept, made.blocks]),
            ));
        }
        // A model of one solid: the cache of the last tree is let go.
        SURFACES.with_borrow_mut(|cache| *cache = MeshCache::new());
        let v = volume(text, resolution)?;
        Ok((
            Made {
                data: crate::view3d::surface_share_floats(&v, resolution, share),
                approximate: v.exhausted(),
            },
            None,
        ))
    }

    /// The contour stack of a volume model across `axis` (0 = u, 1 = v, 2 = w), as
    /// [`crate::view3d::stack_segments`] makes it; `progress(done, total)` after each slice.
    ///
    /// # Errors
    ///
    /// What is wrong with the input, a patch model, or another axis.
    pub fn stack(
        text: &str,
        axis: Axis,
        progress: impl FnMut(usize, usize),
    ) -> Result<Made<Vec<f64>>, Error> {
        stack_share(text, axis, Share::WHOLE, progress)
    }

    /// The slices of share `share` of the contour stack [`stack`] makes, for a page that makes it
    /// in several workers: the shares' segments, one after another, are its segments.
    ///
    /// # Errors
    ///
    /// As [`stack`].
    pub fn stack_share(
        text: &str,
        axis: Axis,
        share: Share,
        progress: impl FnMut(usize, usize),
    ) -> Result<Made<Vec<f64>>, Error> {
        match read_any(text)? {
            ModelSolid::Volume(v) => {
                let (data, approximate) =
                    crate::view3d::stack_share_segments(&v, axis, share, progress);
                Ok(Made { data, approximate })
            }
            ModelSolid::Patch(_) => {
                Err("a contour stack is of volume (3D) models; this is a patch".into())
            }
        }
    }

    /// What the solid of a model file or link measures, as JSON, on what the exports write: a 3D
    /// model's (or a free-form model's result's) closed mesh at `resolution` cells along the
    /// longest side (the mesh export's),
    /// `{"dimension": 3, "resolution", "triangles", "volume", "area", "bbox": [x0, y0, z0, x1,
    /// y1, z1]}`; a 2D model's zero contour at [`super::SVG_RESOLUTION`] cells per side (the SVG
    /// export's), `{"dimension": 2, "resolution", "area", "perimeter", "open"}` (`open`: pieces
    /// that end on the sampled box and bound nothing, left out). Exact for the mesh or the
    /// polylines (the divergence theorem, the shoelace sum), so as near the solid as the
    /// resolution; `progress(done, total)` on the way.
    ///
    /// # Errors
    ///
    /// What is wrong with the input, a resolution outside 2 to 512, a model that may be
    /// unbounded, or nothing to measure (an empty mesh).
    pub fn measure_in_steps(
        text: &str,
        resolution: usize,
        progress: impl FnMut(usize, usize),
    ) -> Result<Made<String>, Error> {
        use bezsolid_core::contour::Measure;
        let (svg_res, svg_acc) = (super::SVG_RESOLUTION, super::SVG_ACCURACY);
        let plane = |lines: &[bezsolid_core::contour::Polyline], approximate| {
            let m = Measure::of(lines);
            let json = serde_json::json!({
                "dimension": 2,
                "resolution": svg_res,
                "area": m.area,
                "perimeter": m.perimeter,
                "open": m.open,
            });
            Made {
                data: json.to_string(),
                approximate,
            }
        };
        let space = |mesh: &Mesh, approximate| -> Result<Made<String>, Error> {
            Ok(Made {
                data: mesh_measure(mesh, resolution)?,
                approximate,
            })
        };
        if crate::freeform::is_free_form(text) {
            let mesh = crate::freeform::headless::result_mesh(text, resolution, progress)?;
            return space(&mesh, 0);
        }
        if let Some(t) = tree(text)? {
            return match &t {
                ModelTree::Plane(p) => {
                    let lines = p.contour(svg_res, svg_acc, None).map_err(unbounded)?;
                    Ok(plane(&lines, 0))
                }
                ModelTree::Space(_) => space(&tree_mesh(&t, resolution, false, progress)?, 0),
            };
        }
        match read_any(text)? {
            ModelSolid::Patch(s) => {
                let lines = solid_contour(&s, svg_res, svg_acc);
                Ok(plane(&lines, s.exhausted()))
            }
            ModelSolid::Volume(_) => {
                let v = volume(text, resolution)?;
                let mesh = v
                    .polygonize_in_steps(resolution, MESH_ACCURACY, progress)
                    .map_err(Error::from)?;
                space(&mesh, v.exhausted())
            }
        }
    }

    /// The HyperFun model of a model file or link: a model of many solids as its tree, one
    /// solid (space-mapped ones with their inverse map) as the exported solid.
    ///
    /// # Errors
    ///
    /// What is wrong with the input, or a space-mapped model past the export's cap
    /// ([`bezsolid_core::hyperfun::MAX_NUMBERS`]).
    pub fn hyperfun(text: &str) -> Result<String, Error> {
        use bezsolid_core::hyperfun::{solid2_hf, solid3_hf, tree_hf};
        let file = read_file(text)?;
        if file.solid.is_tree() {
            return tree_hf(&file).map_err(|e| Error::new(format!("HyperFun: {e}")));
        }
        match file.to_solid()? {
            ModelSolid::Patch(s) => solid2_hf(&s),
            ModelSolid::Volume(s) => solid3_hf(&s),
        }
        .map_err(Error::from)
    }

    /// What a 3D solid's mesh at `resolution` measures, JSON as the page shows it: `dimension` 3,
    /// `resolution`, `triangles`, `volume`, `area`, `bbox` (`[x0, y0, z0, x1, y1, z1]`).
    ///
    /// # Errors
    ///
    /// An empty mesh: nothing to measure.
    pub fn mesh_measure(mesh: &Mesh, resolution: usize) -> Result<String, Error> {
        if mesh.triangles.is_empty() {
            return Err("the solid is empty at this resolution: nothing to measure".into());
        }
        let m = mesh.measure();
        Ok(serde_json::json!({
            "dimension": 3,
            "resolution": resolution,
            "triangles": mesh.triangle_count(),
            "volume": m.volume,
            "area": m.area,
            "bbox": [m.min.x, m.min.y, m.min.z, m.max.x, m.max.y, m.max.z],
        })
        .to_string())
    }

    /// The zero contours of a patch model as SVG.
    ///
    /// # Errors
    ///
    /// What is wrong with the input, or a volume model.
    pub fn svg(text: &str) -> Result<Made<String>, Error> {
        if let Some(t) = tree(text)? {
            let ModelTree::Plane(t) = t else {
                return Err("contour SVG is of 2D models; this is a 3D model".into());
            };
            let Some((lo, hi)) = t.bounds() else {
                return Err(
                    "the model may be unbounded: draw it with `bezsolid contour --box`".into(),
                );
            };
            let lines = t.contour(super::SVG_RESOLUTION, super::SVG_ACCURACY, None)?;
            let (lo, hi) = (glam::DVec2::from_array(lo), glam::DVec2::from_array(hi));
            let cell = (hi - lo) / super::SVG_RESOLUTION as f64;
            return Ok(Made {
                data: bezsolid_core::mesh::svg::contours_svg(&lines, lo - cell, hi + cell),
                approximate: 0,
            });
        }
        match read_any(text)? {
            ModelSolid::Patch(s) => Ok(Made {
                data: super::svg(&s),
                approximate: s.exhausted(),
            }),
            ModelSolid::Volume(_) => Err("contour SVG is of patch models; this is a volume".into()),
        }
    }
}

/// The closed boundary mesh of a volume model at `resolution` cells along the longest side.
///
/// # Errors
///
/// For a patch model, or a resolution out of range.
pub fn mesh(editor: &Editor, resolution: usize) -> Result<Mesh, Error> {
    let volume = editor
        .volume()
        .ok_or("mesh exports are of volume (3D) models; this is a patch: export SVG instead")?;
    volume
        .polygonize(resolution, MESH_ACCURACY)
        .map_err(Error::from)
}

#[cfg(test)]
mod tests {
    use super::*;
    use bezsolid_core::Axis;
    use bezsolid_core::mesh::Format;
    use bezsolid_core::mesh::exchange::ExportFormat;
    use glam::DVec2;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn moved() -> Editor {
        let mut s = Solid2::fig9();
        s.set_point([1, 2], DVec2::new(0.61, 1.2)).unwrap();
        s.set_xi([0, 1], 0.123_456_789_012_345_6).unwrap();
        Editor::new(s)
    }

    fn same_model(a: &Editor, b: &Editor) -> bool {
        model_file(a) == model_file(b)
    }

    #[test]
    fn model_file_and_link_round_trip_exactly() {
        let e = moved();
        let mut other = Editor::new(Solid2::fig9());
        open(&mut other, read_model(&model_json(&e)).unwrap());
        assert!(same_model(&e, &other));
        let link = share_fragment(&e).unwrap();
        let mut third = Editor::new(Solid2::fig9());
        open(&mut third, open_link(&format!("http://h/{link}")).unwrap());
        assert!(same_model(&e, &third));
    }

    #[test]
    fn volumes_open_save_link_and_mesh() {
        let mut e = Editor::new(Solid2::fig9());
        open(&mut e, preset("fish").unwrap());
        assert!(e.volume().is_some());
        let mut back = Editor::new(Solid2::fig9());
        open(&mut back, read_model(&model_json(&e)).unwrap());
        assert!(same_model(&e, &back));
        open(&mut back, open_link(&share_fragment(&e).unwrap()).unwrap());
        assert!(same_model(&e, &back));
        let m = mesh(&e, 24).unwrap();
        assert!(m.check_closed_manifold().is_ok());
        let stl = Format::Stl.write(&m);
        assert_eq!(stl.len(), 84 + 50 * m.triangles.len());
        assert!(
            headless::hyperfun(&model_json(&e))
                .unwrap()
                .contains("my_model(")
        );
        assert!(mesh(&Editor::new(Solid2::fig9()), 24).is_err());
    }

    #[test]
    fn headless_reads_files_and_links_and_meshes() {
        let e = {
            let mut e = Editor::new(Solid2::fig9());
            open(&mut e, preset("blob").unwrap());
            e
        };
        let json = model_json(&e);
        let link = share_fragment(&e).unwrap();
        assert_eq!(headless::model(&link).unwrap(), json);
        assert_eq!(headless::model(&json).unwrap(), json);
        assert_eq!(headless::link(&json).unwrap(), link);
        let stl = headless::mesh(&format!("http://x/{link}"), ExportFormat::Stl, 20).unwrap();
        let m = mesh(&e, 20).unwrap();
        assert_eq!(stl.data, Format::Stl.write(&m));
        assert_eq!(stl.approximate, 0, "a regular net is exact");
        assert!(headless::mesh(&link, ExportFormat::Stl, 1).is_err());
        assert!(headless::mesh(&link, ExportFormat::Stl, 100_000).is_err());
        assert!(
            headless::mesh(
                &model_json(&Editor::new(Solid2::fig9())),
                ExportFormat::Stl,
                20
            )
            .unwrap_err()
            .message()
            .contains("patch")
        );
        let mut calls = Vec::new();
        let stack =
            headless::stack(&link, Axis::W, |done, total| calls.push((done, total))).unwrap();
        assert_eq!(calls, [(1, 3), (2, 3), (3, 3)]);
        assert_eq!(
            (stack.data, stack.approximate),
            crate::view3d::stack_segments(e.volume().unwrap(), bezsolid_core::Axis::W, |_, _| {})
        );
        assert!(headless::stack(&json, Axis::W, |_, _| {}).is_ok());
        assert!(headless::model("#v1.garbage").is_err());
        assert!(headless::model("{ not json").is_err());
    }

    /// Measurements on what the exports make: a volume's mesh file measures what the JSON says
    /// (read back from the STL), near the formula for a ball; a 2D tree's area and perimeter are
    /// its contour's, near a ring's; a free-form result is measured on its mesh; what cannot be
    /// measured says why.
    #[test]
    fn headless_measurements_are_of_what_the_exports_make() {
        let ball = r#"{"format": "bezsolid", "version": 1,
            "solid": {"kind": "sphere", "center": [1, 2, 3], "radius": 0.5}}"#;
        let m: serde_json::Value = serde_json::from_str(
            &headless::measure_in_steps(ball, 48, |_, _| {})
                .unwrap()
                .data,
        )
        .unwrap();
        let stl = headless::mesh(ball, ExportFormat::Stl, 48).unwrap().data;
        let mesh = Format::Stl.read(&stl).unwrap();
        assert_eq!(m["dimension"], 3);
        assert_eq!(m["resolution"], 48);
        assert_eq!(m["triangles"], mesh.triangle_count());
        let (volume, area) = (m["volume"].as_f64().unwrap(), m["area"].as_f64().unwrap());
        // The STL holds f32 coordinates.
        assert!((volume - mesh.volume()).abs() < 1e-5 * volume, "{volume}");
        assert!((area - mesh.area()).abs() < 1e-5 * area, "{area}");
        let pi = std::f64::consts::PI;
        assert!((volume - pi / 6.0).abs() < 0.01 * pi / 6.0, "{volume}");
        assert!((area - pi).abs() < 0.01 * pi, "{area}");
        let bbox: Vec<f64> = m["bbox"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        for (got, want) in bbox.iter().zip([0.5, 1.5, 2.5, 1.5, 2.5, 3.5]) {
            assert!((got - want).abs() < 0.01, "{bbox:?}");
        }

        let ring = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "difference", "of": [
            {"kind": "circle", "center": [0, 0], "radius": 1},
            {"kind": "circle", "center": [0, 0], "radius": 0.5}]}}"#;
        let m: serde_json::Value = serde_json::from_str(
            &headless::measure_in_steps(ring, 48, |_, _| {})
                .unwrap()
                .data,
        )
        .unwrap();
        assert_eq!(m["dimension"], 2);
        assert_eq!(m["resolution"], SVG_RESOLUTION);
        assert_eq!(m["open"], 0);
        let (area, perimeter) = (
            m["area"].as_f64().unwrap(),
            m["perimeter"].as_f64().unwrap(),
        );
        assert!((area - 0.75 * pi).abs() < 1e-3, "{area}");
        assert!((perimeter - 3.0 * pi).abs() < 1e-3, "{perimeter}");
        // A patch: the area its SVG contour encloses.
        let fig9 = model_json(&Editor::new(Solid2::fig9()));
        let m: serde_json::Value = serde_json::from_str(
            &headless::measure_in_steps(&fig9, 48, |_, _| {})
                .unwrap()
                .data,
        )
        .unwrap();
        let lines = solid_contour(&Solid2::fig9(), SVG_RESOLUTION, SVG_ACCURACY);
        let enclosed: f64 = lines.iter().map(|l| l.signed_area()).sum();
        assert_eq!(m["area"].as_f64().unwrap(), enclosed);
        assert!(enclosed > 0.1);

        let free = crate::freeform::FreeForm::new().model_file();
        let free = serde_json::to_string(&free).unwrap();
        let m: serde_json::Value = serde_json::from_str(
            &headless::measure_in_steps(&free, 24, |_, _| {})
                .unwrap()
                .data,
        )
        .unwrap();
        assert_eq!(m["dimension"], 3);
        assert!(m["volume"].as_f64().unwrap() > 0.0);

        let half = r#"{"format": "bezsolid", "version": 1,
            "solid": {"kind": "halfspace", "normal": [0, 0, 1], "offset": 0}}"#;
        let e = headless::measure_in_steps(half, 16, |_, _| {}).unwrap_err();
        assert!(e.message().contains("unbounded"), "{e}");
        assert!(headless::measure_in_steps(ball, 1, |_, _| {}).is_err());
        assert!(headless::measure_in_steps("{ not json", 16, |_, _| {}).is_err());
    }

    #[test]
    fn headless_jobs_take_trees_of_many_solids() {
        let tree = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "blend_union",
            "a0": 0.2, "a1": 1, "a2": 1, "of": [
            {"kind": "sphere", "center": [0, 0, 0], "radius": 1},
            {"kind": "transform", "translate": [1, 0, 0], "solid":
                {"kind": "box", "min": [-0.3, -0.3, -0.3], "max": [0.3, 0.3, 0.3]}}]}}"#;
        let json = headless::model(tree).unwrap();
        let link = headless::link(tree).unwrap();
        assert_eq!(headless::model(&link).unwrap(), json);
        assert_eq!(headless::link(&json).unwrap(), link);
        let stl = headless::mesh(&link, ExportFormat::Stl, 32).unwrap();
        let mesh = Format::Stl.read(&stl.data).unwrap();
        mesh.check_closed_manifold().unwrap();
        let surface = headless::surface(tree, 32).unwrap().data;
        assert_eq!(surface.len(), 18 * mesh.triangles.len());
        // A 2D tree: its contour as SVG; a 3D one has none, a 2D one no mesh.
        let plane = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "union", "of": [
            {"kind": "circle", "center": [0, 0], "radius": 1},
            {"kind": "rectangle", "min": [0, -0.2], "max": [2, 0.2]}]}}"#;
        assert!(headless::svg(plane).unwrap().data.contains("<svg"));
        assert!(headless::svg(tree).is_err());
        assert!(headless::mesh(plane, ExportFormat::Stl, 32).is_err());
        // What cannot be meshed says so.
        let half = r#"{"format": "bezsolid", "version": 1,
            "solid": {"kind": "halfspace", "normal": [0, 0, 1], "offset": 0}}"#;
        let e = headless::mesh(half, ExportFormat::Stl, 16).unwrap_err();
        assert!(e.message().contains("unbounded"), "{e}");
        // The 3D view shows it cut by a box around its bounded parts (a sphere on a half-space):
        // every vertex within the box, some on the half-space's plane.
        let on_floor = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "union", "of": [
            {"kind": "sphere", "center": [0, 0, 1], "radius": 1},
            {"kind": "halfspace", "normal": [0, 0, 1], "offset": 0}]}}"#;
        let surface = headless::surface(on_floor, 24).unwrap().data;
        assert!(surface.len() > 18 * 100);
        for v in surface.chunks_exact(6) {
            // The sphere's box [-1, 1]² × [0, 2], a quarter (0.5) larger on every side.
            assert!(v[..3].iter().all(|c| c.abs() <= 2.5 + 1e-4), "{v:?}");
        }
        assert!(
            surface.chunks_exact(6).any(|v| v[2].abs() < 1e-6),
            "the floor"
        );
        let bad = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "union", "of": [
            {"kind": "sphere", "center": [0, 0, 0], "radius": -1}]}}"#;
        let e = headless::mesh(bad, ExportFormat::Stl, 16).unwrap_err();
        assert!(e.message().contains("solid.of"), "{e}");
    }

    #[test]
    fn bad_files_and_links_say_what_is_wrong() {
        assert!(
            read_model("{")
                .unwrap_err()
                .message()
                .contains("not a bezsolid model file")
        );
        assert!(read_model(r#"{"format":"bezsolid","version":9,"solid":{"kind":"patch","degree":[1,1],"points":[]}}"#)
            .unwrap_err()
            .message()
            .contains("version 9"));
        assert!(
            open_link("#v1.AAAA")
                .unwrap_err()
                .message()
                .contains("damaged")
        );
        assert!(
            read_model(&" ".repeat(MAX_MODEL_BYTES + 1))
                .unwrap_err()
                .message()
                .contains("at most")
        );
        // Spaces past a link's cap are too long, not an empty link, however they are read.
        let spaces = " ".repeat(1 << 20);
        for e in [
            read_any(&spaces).unwrap_err(),
            open_link(&spaces).unwrap_err(),
            read_file(&spaces).unwrap_err(),
            crate::freeform::read_file(&spaces).unwrap_err(),
        ] {
            assert!(
                e.message().contains("a link holds at most"),
                "{}",
                e.message()
            );
        }
        assert!(preset("whale").is_err());
    }

    /// A degree-16 volume whose control points are those of the regular grid in shuffled order:
    /// it folds over itself everywhere.
    fn shuffled_volume() -> String {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut at: Vec<[usize; 3]> = (0..17 * 17 * 17)
            .map(|k| [k / 289, k / 17 % 17, k % 17])
            .collect();
        for k in (1..at.len()).rev() {
            at.swap(k, (next() % (k as u64 + 1)) as usize);
        }
        let points: Vec<String> = at
            .iter()
            .map(|[i, j, l]| {
                let xi = (next() % 2001) as f64 / 1000.0 - 1.0;
                format!(
                    "[{},{},{},{xi}]",
                    *i as f64 / 16.0,
                    *j as f64 / 16.0,
                    *l as f64 / 16.0
                )
            })
            .collect();
        format!(
            r#"{{"format":"bezsolid","version":1,"solid":{{"kind":"volume","degree":[16,16,16],"points":[{}]}}}}"#,
            points.join(",")
        )
    }

    #[test]
    fn exports_of_nets_that_fold_everywhere_say_they_are_approximate() {
        let made = headless::mesh(&shuffled_volume(), ExportFormat::Stl, 16).unwrap();
        assert!(made.data.len() >= 84);
        assert!(made.approximate > 0, "{}", made.approximate);
    }

    #[test]
    fn exports_hold_the_model() {
        let e = moved();
        let svg = svg(e.solid());
        assert!(svg.contains("<path"));
        let made = headless::svg(&patch_json(&e)).unwrap();
        assert_eq!(made.data, svg, "the worker's SVG is the same");
        assert_eq!(made.approximate, 0);
        // A space mapping's HyperFun carries its inverse map; its model file and its link give
        // the same.
        let mapped = headless::hyperfun(&model_json(&e)).unwrap();
        assert!(mapped.contains("space-mapped") && mapped.contains("endloop;"));
        assert_eq!(
            headless::hyperfun(&share_fragment(&e).unwrap()).unwrap(),
            mapped
        );
        assert!(
            headless::hyperfun(&model_json(&Editor::new(Solid2::fig9())))
                .unwrap()
                .contains("my_model(")
        );
        // A model of many solids: its tree.
        let tree = r#"{"format": "bezsolid", "version": 1, "solid": {"kind": "union", "of": [
            {"kind": "sphere", "center": [0, 0, 0], "radius": 1},
            {"kind": "box", "min": [0.5, -0.3, -0.3], "max": [1.4, 0.3, 0.3]}]}}"#;
        assert!(headless::hyperfun(tree).unwrap().contains("my_model("));
        assert!(headless::hyperfun("{").is_err());
    }
}
