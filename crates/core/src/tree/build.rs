//! Checking and compiling a model file's tree: the kinds and their dimension, the caps, each
//! node's numbers ([`super::check`]), the transforms' inverse maps, and the postfix program over
//! the leaves.

use alloc::boxed::Box;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;

use super::check::{self, bounded, finite, finite_array, non_zero, positive};
use super::shape::{Regular, RegularCells, Shape};
use super::{Affine, Leaf, MAX_DEPTH, MAX_NODES, ModelTree, Step, Tree, TreeError, bounds, error};
use crate::dim::{Dim, Dimension};
use crate::model::{CoordAxis, ModelError, ModelFile, Rotation, SolidSpec};
use crate::solid::Solid;
use crate::tensor::Tensor;

impl ModelFile {
    /// Checks the header and the tree of `solid` (a single patch or volume is a tree of one leaf)
    /// and compiles it.
    ///
    /// # Errors
    ///
    /// [`ModelError`] for another format or version, a free-form model, a script or a HyperFun
    /// program ([`ModelError::Kind`]), or a tree that breaks a rule ([`ModelError::Tree`], naming the
    /// node's path).
    pub fn to_tree(&self) -> Result<ModelTree, ModelError> {
        self.check_header()?;
        // A program alone is a model of its own (the HyperFun mode's, not cut by a tree's rules);
        // a tree may hold one as a leaf.
        if matches!(self.solid, SolidSpec::Hyperfun { .. }) {
            return Err(ModelError::Kind(crate::model::HYPERFUN_ALONE));
        }
        let dimension = dimension_of(&self.solid).map_err(ModelError::Tree)?;
        Ok(if dimension == 2 {
            ModelTree::Plane(Builder::<2>::build(&self.solid)?)
        } else {
            ModelTree::Space(Builder::<3>::build(&self.solid)?)
        })
    }
}

/// The dimension of a node's kind: `Some(2)`, `Some(3)`, or `None` for an operation or transform.
fn kind_dimension(spec: &SolidSpec) -> Result<Option<usize>, &'static str> {
    Ok(match spec {
        SolidSpec::Patch { .. }
        | SolidSpec::Circle { .. }
        | SolidSpec::Rectangle { .. }
        | SolidSpec::Halfplane { .. } => Some(2),
        SolidSpec::Volume { .. }
        | SolidSpec::Sphere { .. }
        | SolidSpec::Box { .. }
        | SolidSpec::Cylinder { .. }
        | SolidSpec::Torus { .. }
        | SolidSpec::Halfspace { .. } => Some(3),
        SolidSpec::Piecewise { cells, .. } => match cells.len() {
            2 => Some(2),
            3 => Some(3),
            _ => {
                return Err(
                    "a piecewise solid's \"cells\" are [cu, cv] (a patch) or [cu, cv, cw] (a volume)",
                );
            }
        },
        SolidSpec::Esc { .. } => {
            return Err("a free-form model is a model of its own, not a node of a tree");
        }
        SolidSpec::Plasm { .. } => {
            return Err("a PLaSM script is a model of its own, not a node of a tree");
        }
        // A HyperFun program is of x[3], as HyperFun's polygonizer takes it.
        SolidSpec::Hyperfun { .. } => Some(3),
        _ => None,
    })
}

/// The children of a node, each with its path's step (`.of[i]`, or a transform's `.solid`).
fn children(spec: &SolidSpec) -> Vec<(String, &SolidSpec)> {
    let transform = matches!(spec, SolidSpec::Transform { .. } | SolidSpec::Part { .. });
    spec.children()
        .iter()
        .enumerate()
        .map(|(i, c)| match transform {
            true => (String::from(".solid"), c),
            false => (format!(".of[{i}]"), c),
        })
        .collect()
}

/// The dimension of the tree: that of its first leaf, found depth-first (without recursion; the
/// builder checks the caps and names the node past them).
fn dimension_of(root: &SolidSpec) -> Result<usize, TreeError> {
    let mut todo = alloc::vec![(String::from("solid"), root)];
    while let Some((path, spec)) = todo.pop() {
        match kind_dimension(spec) {
            Err(message) => return Err(error(&path, message)),
            Ok(Some(d)) => return Ok(d),
            Ok(None) => {
                let mut kids = children(spec);
                kids.reverse();
                for (step, child) in kids {
                    todo.push((format!("{path}{step}"), child));
                }
            }
        }
    }
    Err(error(
        "solid",
        "the tree has no solid in it (an operation needs nodes in \"of\")",
    ))
}

/// Compiles a tree of `D` dimensions, checking each node on the way.
struct Builder<const D: usize>
where
    Dim<D>: Dimension<D>,
{
    leaves: Vec<Leaf<D>>,
    steps: Vec<Step>,
    nodes: usize,
    depth: usize,
    stack: usize,
    /// The least and greatest factor by which the transforms above the node being built scale
    /// lengths.
    scales: (f64, f64),
}

impl<const D: usize> Builder<D>
where
    Dim<D>: Dimension<D>,
{
    fn build(root: &SolidSpec) -> Result<Tree<D>, ModelError> {
        let mut b = Self {
            leaves: Vec::new(),
            steps: Vec::new(),
            nodes: 0,
            depth: 0,
            stack: 0,
            scales: (1.0, 1.0),
        };
        b.node(root, "solid", None, 1)?;
        let boxes = bounds::boxes(root, 0.0, &Affine::IDENTITY, &mut b.leaves.iter());
        let bounds = boxes.as_deref().map(bounds::hull_of);
        let clusters = boxes.map(|b| bounds::clusters(&b)).unwrap_or_default();
        let parts = bounds::parts_hull(root, &Affine::IDENTITY, &mut b.leaves.iter());
        let mut middles = Vec::new();
        bounds::leaf_middles(root, &Affine::IDENTITY, &mut b.leaves.iter(), &mut middles);
        Ok(Tree {
            leaves: b.leaves,
            steps: b.steps,
            stack: b.stack,
            bounds,
            parts,
            middles,
            clusters,
        })
    }

    /// Compiles `spec` at `path`, `depth` deep, under the map `map` (space to this node's
    /// coordinates). `height` is the evaluation stack's height after it pushes its value.
    fn node(
        &mut self,
        spec: &SolidSpec,
        path: &str,
        map: Option<Affine<D>>,
        height: usize,
    ) -> Result<(), ModelError> {
        let tree_error = |p: &str, m: String| ModelError::Tree(error(p, m));
        self.nodes += 1;
        if self.nodes > MAX_NODES {
            return Err(tree_error(
                path,
                format!("the tree has more than {MAX_NODES} nodes"),
            ));
        }
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(tree_error(
                path,
                format!("the tree is more than {MAX_DEPTH} nodes deep"),
            ));
        }
        self.stack = self.stack.max(height);
        match kind_dimension(spec) {
            Err(m) => return Err(tree_error(path, m.into())),
            Ok(Some(d)) if d != D => {
                return Err(tree_error(
                    path,
                    format!("a {d}D node in a {D}D tree: a tree is all 2D or all 3D"),
                ));
            }
            _ => {}
        }
        let field = |name: &str| format!("{path}.{name}");
        match spec {
            SolidSpec::Patch { .. } | SolidSpec::Volume { .. } => {
                // A single solid's error reads as it always has; a leaf's names its path.
                let solid = bezier::<D>(spec).map_err(|e| match path {
                    "solid" => ModelError::Solid(e),
                    _ => tree_error(path, format!("invalid solid: {e}")),
                })?;
                let regular = Regular::of(&solid).map(Box::new);
                self.leaf(Shape::Bezier(Box::new(solid), regular), map);
            }
            SolidSpec::Piecewise {
                cells,
                degree,
                points,
            } => {
                let solid = piecewise::<D>(cells, degree, points)
                    .map_err(|e| tree_error(path, format!("invalid piecewise solid: {e}")))?;
                let regular = RegularCells::of(&solid).map(Box::new);
                self.leaf(Shape::Piecewise(Box::new(solid), regular), map);
            }
            SolidSpec::Circle { center, radius } => self.ball(center, *radius, path, map)?,
            SolidSpec::Sphere { center, radius } => self.ball(center, *radius, path, map)?,
            SolidSpec::Rectangle { min, max } => self.cuboid(min, max, path, map)?,
            SolidSpec::Box { min, max } => self.cuboid(min, max, path, map)?,
            SolidSpec::Cylinder {
                center,
                axis,
                radius,
            } => {
                let center = finite_array::<D>(center, &field("center"))?;
                positive(*radius, &field("radius"))?;
                self.leaf(
                    Shape::Cylinder {
                        center,
                        axis: axis_index(*axis),
                        radius: *radius,
                    },
                    map,
                );
            }
            SolidSpec::Torus {
                center,
                axis,
                major,
                minor,
            } => {
                let center = finite_array::<D>(center, &field("center"))?;
                positive(*major, &field("major"))?;
                positive(*minor, &field("minor"))?;
                self.leaf(
                    Shape::Torus {
                        center,
                        axis: axis_index(*axis),
                        major: *major,
                        minor: *minor,
                    },
                    map,
                );
            }
            SolidSpec::Halfplane { normal, offset } => self.half(normal, *offset, path, map)?,
            SolidSpec::Halfspace { normal, offset } => self.half(normal, *offset, path, map)?,
            SolidSpec::Union { of } => self.operation(of, path, map, height, 2, Step::Union)?,
            SolidSpec::Intersection { of } => {
                self.operation(of, path, map, height, 2, Step::Intersection)?;
            }
            SolidSpec::Difference { of } => {
                self.operation(of, path, map, height, 2, Step::Difference)?;
            }
            SolidSpec::BlendUnion { of, a0, a1, a2 }
            | SolidSpec::BlendIntersection { of, a0, a1, a2 } => {
                bounded(*a0, &field("a0"))?;
                non_zero(*a1, &field("a1"))?;
                non_zero(*a2, &field("a2"))?;
                let union = matches!(spec, SolidSpec::BlendUnion { .. });
                let step = Step::Blend {
                    union,
                    a0: *a0,
                    a1: *a1,
                    a2: *a2,
                };
                self.operation(of, path, map, height, 0, |_| step)?;
            }
            SolidSpec::Morph { of, t } => {
                bounded(*t, &field("t"))?;
                let t = *t;
                self.operation(of, path, map, height, 0, |_| Step::Morph(t))?;
            }
            SolidSpec::Transform {
                solid,
                translate,
                rotate,
                scale,
            } => {
                let inverse = transform_inverse::<D>(path, translate, rotate, scale)?;
                let outer = self.scales;
                if let Some(scale) = scale {
                    self.scales = check::scale_range(outer, scale, &field("scale"))?;
                }
                let map = Some(map.map_or(inverse, |outer| inverse.after(&outer)));
                self.node(solid, &field("solid"), map, height)?;
                self.scales = outer;
            }
            SolidSpec::Part { solid, name, .. } => {
                if name.len() > crate::model::MAX_NAME_BYTES {
                    return Err(tree_error(
                        &field("name"),
                        format!(
                            "the name is {} bytes; a name is at most {}",
                            name.len(),
                            crate::model::MAX_NAME_BYTES
                        ),
                    ));
                }
                self.node(solid, &field("solid"), map, height)?;
            }
            SolidSpec::Hyperfun { program, bounds } => {
                let leaf = hyperfun::<D>(program, *bounds, path)?;
                self.leaf(Shape::Hyperfun(Box::new(leaf)), map);
            }
            SolidSpec::Esc { .. } | SolidSpec::Plasm { .. } => {
                unreachable!("refused by kind_dimension")
            }
        }
        self.depth -= 1;
        Ok(())
    }

    fn ball(
        &mut self,
        center: &[f64],
        radius: f64,
        path: &str,
        map: Option<Affine<D>>,
    ) -> Result<(), ModelError> {
        let center = finite_array::<D>(center, &format!("{path}.center"))?;
        positive(radius, &format!("{path}.radius"))?;
        self.leaf(Shape::Ball { center, radius }, map);
        Ok(())
    }

    fn cuboid(
        &mut self,
        min: &[f64],
        max: &[f64],
        path: &str,
        map: Option<Affine<D>>,
    ) -> Result<(), ModelError> {
        let lo = finite_array::<D>(min, &format!("{path}.min"))?;
        let hi = finite_array::<D>(max, &format!("{path}.max"))?;
        if (0..D).any(|i| lo[i] >= hi[i]) {
            return Err(ModelError::Tree(error(
                &format!("{path}.max"),
                "every coordinate of max must be above min's",
            )));
        }
        self.leaf(Shape::Box { min: lo, max: hi }, map);
        Ok(())
    }

    fn half(
        &mut self,
        normal: &[f64],
        offset: f64,
        path: &str,
        map: Option<Affine<D>>,
    ) -> Result<(), ModelError> {
        let normal = finite_array::<D>(normal, &format!("{path}.normal"))?;
        if normal.iter().all(|&n| n == 0.0) {
            return Err(ModelError::Tree(error(
                &format!("{path}.normal"),
                "the normal is zero",
            )));
        }
        bounded(offset, &format!("{path}.offset"))?;
        self.leaf(Shape::Half { normal, offset }, map);
        Ok(())
    }

    fn leaf(&mut self, shape: Shape<D>, map: Option<Affine<D>>) {
        self.steps.push(Step::Leaf(self.leaves.len()));
        self.leaves.push(Leaf { shape, map });
    }

    /// An operation over `of`: at least `min` nodes (exactly 2 where `min` is 0).
    fn operation(
        &mut self,
        of: &[SolidSpec],
        path: &str,
        map: Option<Affine<D>>,
        height: usize,
        min: usize,
        step: impl Fn(usize) -> Step,
    ) -> Result<(), ModelError> {
        let count_ok = if min == 0 {
            of.len() == 2
        } else {
            of.len() >= min
        };
        if !count_ok {
            let want = if min == 0 { "exactly 2" } else { "2 or more" };
            return Err(ModelError::Tree(error(
                &format!("{path}.of"),
                format!("{} nodes; this operation takes {want}", of.len()),
            )));
        }
        for (i, child) in of.iter().enumerate() {
            self.node(child, &format!("{path}.of[{i}]"), map, height + i)?;
        }
        self.steps.push(step(of.len()));
        Ok(())
    }
}

fn axis_index(axis: CoordAxis) -> usize {
    axis.index()
}

/// A Bézier leaf's solid, as a single-solid model file builds it.
fn bezier<const D: usize>(spec: &SolidSpec) -> Result<Solid<D>, crate::solid::SolidError>
where
    Dim<D>: Dimension<D>,
{
    use crate::solid::SolidError;
    let (degree, points): (&[usize], Vec<&[f64]>) = match spec {
        SolidSpec::Patch { degree, points } => (degree, points.iter().map(|p| &p[..]).collect()),
        SolidSpec::Volume { degree, points } => (degree, points.iter().map(|p| &p[..]).collect()),
        _ => unreachable!("a Bézier leaf"),
    };
    // The kind's dimension was checked against the tree's.
    let degree: [usize; D] = degree.try_into().map_err(|_| SolidError::Index {
        index: degree.len(),
        len: D,
    })?;
    let controls = points
        .iter()
        .map(|p| Dim::<D>::control(core::array::from_fn(|c| p[c]), p[D]))
        .collect();
    let net = Tensor::try_new(degree, controls).map_err(SolidError::from)?;
    Solid::try_from_net(net)
}

/// The piecewise solid of a [`SolidSpec::Piecewise`]'s numbers.
pub(crate) fn piecewise<const D: usize>(
    cells: &[usize],
    degree: &[usize],
    points: &[Vec<f64>],
) -> Result<crate::piecewise::Piecewise<D>, crate::piecewise::PiecewiseError>
where
    Dim<D>: Dimension<D>,
{
    use crate::piecewise::{Piecewise, PiecewiseError};
    let dimension = PiecewiseError::Dimension {
        cells: cells.len(),
        degree: degree.len(),
    };
    let cells: [usize; D] = cells.try_into().map_err(|_| dimension.clone())?;
    let degree: [usize; D] = degree.try_into().map_err(|_| dimension)?;
    let controls = points
        .iter()
        .enumerate()
        .map(|(index, p)| {
            if p.len() == D + 1 {
                Ok(Dim::<D>::control(core::array::from_fn(|c| p[c]), p[D]))
            } else {
                Err(PiecewiseError::Point {
                    index,
                    got: p.len(),
                    want: D + 1,
                })
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    Piecewise::new(cells, degree, controls)
}

/// `M⁻¹` of the transform `M = T · Rz · Ry · Rx · S` (in 2D `T · R · S`).
fn transform_inverse<const D: usize>(
    path: &str,
    translate: &Option<Vec<f64>>,
    rotate: &Option<Rotation>,
    scale: &Option<Vec<f64>>,
) -> Result<Affine<D>, ModelError> {
    let t = match translate {
        Some(t) => finite_array::<D>(t, &format!("{path}.translate"))?,
        None => [0.0; D],
    };
    let s = match scale {
        Some(s) => {
            let s = finite_array::<D>(s, &format!("{path}.scale"))?;
            for (i, v) in s.iter().enumerate() {
                non_zero(*v, &format!("{path}.scale[{i}]"))?;
            }
            s
        }
        None => [1.0; D],
    };
    // R as a matrix (row-major), from the angles in degrees.
    let rotation_path = format!("{path}.rotate");
    let mut r = Affine::<D>::IDENTITY.m;
    match (rotate, D) {
        (None, _) => {}
        (Some(Rotation::Angle(a)), 2) => {
            finite(*a, &rotation_path)?;
            let (sin, cos) = sin_cos(*a);
            r[0][0] = cos;
            r[0][1] = -sin;
            r[1][0] = sin;
            r[1][1] = cos;
        }
        (Some(Rotation::Angles(angles)), 3) => {
            for (i, a) in angles.iter().enumerate() {
                finite(*a, &format!("{rotation_path}[{i}]"))?;
            }
            let m = rotation3(*angles);
            for (row, m_row) in r.iter_mut().zip(m) {
                row.copy_from_slice(&m_row);
            }
        }
        (Some(_), _) => {
            return Err(ModelError::Tree(error(
                &rotation_path,
                if D == 2 {
                    "a 2D rotation is one angle in degrees"
                } else {
                    "a 3D rotation is [rx, ry, rz] in degrees"
                },
            )));
        }
    }
    // M⁻¹ p = S⁻¹ Rᵀ (p − t).
    let m: [[f64; D]; D] = core::array::from_fn(|i| core::array::from_fn(|j| r[j][i] / s[i]));
    let shift: [f64; D] = core::array::from_fn(|i| -(0..D).map(|j| m[i][j] * t[j]).sum::<f64>());
    Ok(Affine { m, t: shift })
}

/// `(sin, cos)` of `degrees`.
pub(crate) fn sin_cos(degrees: f64) -> (f64, f64) {
    let radians = degrees.to_radians();
    #[cfg(feature = "std")]
    {
        radians.sin_cos()
    }
    #[cfg(not(feature = "std"))]
    {
        (libm::sin(radians), libm::cos(radians))
    }
}

/// `Rz · Ry · Rx` of angles `[rx, ry, rz]` in degrees.
pub(crate) fn rotation3([rx, ry, rz]: [f64; 3]) -> [[f64; 3]; 3] {
    let (sx, cx) = sin_cos(rx);
    let (sy, cy) = sin_cos(ry);
    let (sz, cz) = sin_cos(rz);
    let x = [[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]];
    let y = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
    let z = [[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]];
    let mul = |a: [[f64; 3]; 3], b: [[f64; 3]; 3]| -> [[f64; 3]; 3] {
        core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
    };
    mul(mul(z, y), x)
}

/// A HyperFun leaf: its program parsed as HyperFun reads it, within its box (HyperFun's
/// polygonizer's default where the node has none).
fn hyperfun<const D: usize>(
    program: &str,
    bounds: Option<[[f64; 3]; 2]>,
    path: &str,
) -> Result<super::shape::HfLeaf<D>, ModelError> {
    let tree_error = |p: &str, m: String| ModelError::Tree(error(p, m));
    if program.len() > crate::hyperfun::read::MAX_SOURCE_BYTES {
        return Err(ModelError::ProgramTooLong(program.len()));
    }
    let [lo, hi] = bounds.unwrap_or(crate::model::DEFAULT_HYPERFUN_BOX);
    if !(0..3).all(|i| (hi[i] - lo[i]).is_finite() && lo[i] < hi[i]) {
        return Err(tree_error(
            &format!("{path}.box"),
            "a HyperFun program's box is [[x0, y0, z0], [x1, y1, z1]], finite, with x0 < x1, \
             y0 < y1 and z0 < z1"
                .into(),
        ));
    }
    let parsed = crate::hyperfun::read::Program::parse(program).map_err(|e| {
        tree_error(
            &format!("{path}.program"),
            format!("invalid HyperFun program: {e}"),
        )
    })?;
    // Its main body is called as the tree's export calls it, with a point and one parameter.
    if parsed.dims() != [3, 1, 1] {
        let [x, a, s] = parsed.dims();
        return Err(tree_error(
            &format!("{path}.program"),
            format!(
                "a HyperFun part's model is `{}(x[3], a[1])` (with no `s` array or `s[1]`), not \
                 one of x[{x}], a[{a}], s[{s}]",
                parsed.body()
            ),
        ));
    }
    if parsed.cells() > super::shape::HF_MAX_CELLS {
        return Err(tree_error(
            &format!("{path}.program"),
            format!(
                "a HyperFun part's arrays and variables hold {} numbers; a part holds at most {}",
                parsed.cells(),
                super::shape::HF_MAX_CELLS
            ),
        ));
    }
    Ok(super::shape::HfLeaf {
        text: program.into(),
        program: parsed,
        min: core::array::from_fn(|i| lo[i]),
        max: core::array::from_fn(|i| hi[i]),
        limit: core::sync::atomic::AtomicU64::new(super::shape::HF_POINT_OPERATIONS),
    })
}
