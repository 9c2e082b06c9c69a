//! Where the parts lie: the transforms above a node, its map to space or the plane, and its
//! bounds.

use super::*;

/// The numbers of a transform node in 3D: `T`, the angles of `R` in degrees (one angle is about
/// z) and `S`, the file's defaults where it has none; `None` for other nodes.
pub(super) fn transform_numbers(spec: &SolidSpec) -> Option<(DVec3, [f64; 3], DVec3)> {
    let SolidSpec::Transform {
        translate,
        rotate,
        scale,
        ..
    } = spec
    else {
        return None;
    };
    let v = |x: &Option<Vec<f64>>, default: f64| {
        let x = x.as_deref().unwrap_or(&[]);
        DVec3::from_array(core::array::from_fn(|i| {
            x.get(i).copied().unwrap_or(default)
        }))
    };
    let r = match rotate {
        Some(Rotation::Angles(r)) => *r,
        Some(Rotation::Angle(a)) => [0.0, 0.0, *a],
        None => [0.0; 3],
    };
    Some((v(translate, 0.0), r, v(scale, 1.0)))
}

/// `Rz · Ry · Rx · S` (DESIGN §5), angles in degrees.
pub(super) fn linear(rotate: [f64; 3], scale: DVec3) -> DMat3 {
    DMat3::from_rotation_z(rotate[2].to_radians())
        * DMat3::from_rotation_y(rotate[1].to_radians())
        * DMat3::from_rotation_x(rotate[0].to_radians())
        * DMat3::from_diagonal(scale)
}

/// `T · Rz · Ry · Rx · S` of a transform node in 3D, identity for other nodes.
pub(super) fn node_map(spec: &SolidSpec) -> DAffine3 {
    transform_numbers(spec).map_or(DAffine3::IDENTITY, |(t, r, s)| {
        DAffine3::from_mat3_translation(linear(r, s), t)
    })
}

impl Parts {
    /// Whether a Bézier part of the tree (as `editor` has the open one) is space-mapped.
    #[must_use]
    pub fn has_space_mapped_part(&self, editor: &Editor) -> bool {
        let root = self.root(editor);
        let mut todo = vec![&root];
        while let Some(spec) = todo.pop() {
            if is_bezier(spec) {
                let mapped = match ModelFile::from_spec(spec.clone()).to_solid() {
                    Ok(bezsolid_core::model::ModelSolid::Patch(s)) => s.is_space_mapped(),
                    Ok(bezsolid_core::model::ModelSolid::Volume(v)) => v.is_space_mapped(),
                    Err(_) => false,
                };
                if mapped {
                    return true;
                }
            }
            todo.extend(spec.children());
        }
        false
    }

    /// The map from the coordinates of the node at `path` to space: the transforms above it
    /// (3D trees; identity in 2D).
    #[must_use]
    pub fn placement(&self, path: &[usize]) -> DAffine3 {
        if self.outline.dimension() != 3 {
            return DAffine3::IDENTITY;
        }
        let mut map = DAffine3::IDENTITY;
        for k in 0..path.len() {
            if let Some(node) = self.outline.node(&path[..k]) {
                map *= node_map(node);
            }
        }
        map
    }

    /// The map from the coordinates of the node at `path` to the plane: the transforms above it
    /// (`T · R · S` each), for a 2D model; identity in 3D.
    #[must_use]
    pub fn placement2(&self, path: &[usize]) -> DAffine2 {
        if self.outline.dimension() != 2 {
            return DAffine2::IDENTITY;
        }
        (0..path.len())
            .filter_map(|k| self.outline.node(&path[..k]).and_then(transform_numbers))
            .fold(DAffine2::IDENTITY, |map, (t, r, s)| {
                // A 2D transform's one angle is about z (see `transform_numbers`).
                map * DAffine2::from_scale_angle_translation(
                    s.truncate(),
                    r[2].to_radians(),
                    t.truncate(),
                )
            })
    }

    /// The box in space of the node at `path` (its bounds moved by the transforms above it), if
    /// it is bounded.
    #[must_use]
    pub fn bounds_of(&self, path: &[usize], editor: &Editor) -> Option<(DVec3, DVec3)> {
        let (lo, hi) = self.local_bounds(path, editor)?;
        let map = self.placement(path);
        let corners = (0..8).map(|c| {
            map.transform_point3(DVec3::new(
                if c & 1 == 0 { lo.x } else { hi.x },
                if c & 2 == 0 { lo.y } else { hi.y },
                if c & 4 == 0 { lo.z } else { hi.z },
            ))
        });
        Some(
            corners.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), p| {
                (a.min(p), b.max(p))
            }),
        )
    }

    /// The box of the node at `path` in its own coordinates (2D boxes have z = 0).
    pub(super) fn local_bounds(&self, path: &[usize], editor: &Editor) -> Option<(DVec3, DVec3)> {
        let root = self.root(editor);
        let node = path
            .iter()
            .try_fold(&root, |spec, &i| spec.children().get(i))?;
        Some(match ModelFile::from_spec(node.clone()).to_tree().ok()? {
            ModelTree::Space(t) => {
                let (lo, hi) = t.bounds()?;
                (DVec3::from_array(lo), DVec3::from_array(hi))
            }
            ModelTree::Plane(t) => {
                let (lo, hi) = t.bounds()?;
                (DVec3::new(lo[0], lo[1], 0.0), DVec3::new(hi[0], hi[1], 0.0))
            }
        })
    }

    /// Where a new node goes: at the right of the selection's box (the origin for an unbounded
    /// one).
    pub(super) fn beside(&self, editor: &Editor) -> DVec3 {
        // In the coordinates of the selection's parent, where the new node goes.
        match self.local_bounds(self.outline.selected(), editor) {
            Some((lo, hi)) if (hi - lo).is_finite() => {
                let c = 0.5 * (lo + hi);
                DVec3::new(hi.x, c.y, c.z)
            }
            _ => DVec3::ZERO,
        }
    }
}
