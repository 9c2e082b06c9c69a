//! The outline of a model of many solids: its tree (DESIGN §5) as the page's outliner edits it,
//! a node at a time. A node is named by its [`NodePath`], the child indices from the root (a
//! transform's node is its child 0).
//!
//! Every edit builds the new tree beside the old one and checks it as a model file is checked
//! ([`ModelFile::to_tree`]); a tree that breaks a rule is refused with the rule's message and the
//! outline is unchanged. What an edit does:
//!
//! - [`Outline::add`]: a primitive or a Bézier solid joins the selected operation of any arity
//!   (union, intersection, difference), or the one the selected node is an operand of, or else a
//!   union with the selected node; the new node is selected;
//! - [`Outline::wrap`]: an operation or a transform takes the selected node's place, with it as
//!   its first operand (and a small sphere as the second where two are needed);
//! - [`Outline::remove`]: the selected node leaves its operation (an operation left with one
//!   operand becomes that operand); the root stays;
//! - [`Outline::reorder`]: the selected node moves among its siblings;
//! - [`Outline::set`]: a number of the selected node (`radius`, `center[1]`, `a0`, `t`,
//!   `translate[0]`, `rotate[2]`, `scale[1]`, …); [`Outline::fields`] lists them;
//! - [`Outline::replace`]: a node replaced whole (a Bézier leaf edited in the control-point
//!   editors).

use bezsolid_core::model::{CoordAxis, ModelFile, Rotation, SolidSpec};
use bezsolid_core::tree::ModelTree;
use bezsolid_core::{Solid2, Solid3};
use glam::{DVec2, DVec3};

use crate::error::Error;

/// The child indices from the root to a node.
pub type NodePath = Vec<usize>;

/// A node to add.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewNode {
    /// A ball (3D) or a disc (2D).
    Sphere,
    /// A box (3D) or a rectangle (2D).
    Box,
    /// An infinite cylinder along z (3D).
    Cylinder,
    /// A torus about z (3D).
    Torus,
    /// A half-space (3D) or half-plane (2D).
    Half,
    /// A regular 4 × 4 (× 4) Bézier patch or volume of the tree's dimension.
    Bezier,
    /// A HyperFun program (3D): a ball blended with a torus, in a box around it.
    Hyperfun,
}

/// An operation to put around the selected node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    /// `f1 | f2 | …`.
    Union,
    /// `f1 & f2 & …`.
    Intersection,
    /// `f1 & −f2 & …`.
    Difference,
    /// A blended union.
    BlendUnion,
    /// A blended intersection.
    BlendIntersection,
    /// A morph.
    Morph,
    /// A move: translation, rotation, scale.
    Transform,
}

/// One row of the outliner.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The node.
    pub path: NodePath,
    /// How deep it is (the root is 0).
    pub depth: usize,
    /// What it is, for people: `Union`, `Sphere r = 0.5`, `Bézier volume 4 × 4 × 4`, …
    pub label: String,
    /// Whether it is a Bézier patch or volume, or a piecewise one the editor takes (its control
    /// points edit in the 2D and 3D views).
    pub bezier: bool,
    /// Whether the views leave it out: it is a hidden part, or inside one.
    pub hidden: bool,
}

/// A model of many solids, with a selected node.
#[derive(Clone, Debug, PartialEq)]
pub struct Outline {
    root: SolidSpec,
    dim: usize,
    selected: NodePath,
}

/// An operation of any arity's operands (union, intersection, difference): where a new node joins.
fn variadic_mut(spec: &mut SolidSpec) -> Option<&mut Vec<SolidSpec>> {
    match spec {
        SolidSpec::Union { .. } | SolidSpec::Intersection { .. } | SolidSpec::Difference { .. } => {
            spec.operands_mut()
        }
        _ => None,
    }
}

fn label(spec: &SolidSpec) -> String {
    let v = |x: &[f64]| {
        x.iter()
            .map(|c| format!("{}", (c * 1000.0).round() / 1000.0))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match spec {
        SolidSpec::Patch { degree, .. } => {
            format!("Bézier patch {} × {}", degree[0] + 1, degree[1] + 1)
        }
        SolidSpec::Volume { degree, .. } => format!(
            "Bézier volume {} × {} × {}",
            degree[0] + 1,
            degree[1] + 1,
            degree[2] + 1
        ),
        SolidSpec::Circle { center, radius } => format!("Circle ({}) r = {radius}", v(center)),
        SolidSpec::Sphere { center, radius } => format!("Sphere ({}) r = {radius}", v(center)),
        SolidSpec::Rectangle { min, max } => format!("Rectangle ({}) to ({})", v(min), v(max)),
        SolidSpec::Box { min, max } => format!("Box ({}) to ({})", v(min), v(max)),
        SolidSpec::Cylinder { axis, radius, .. } => {
            format!("Cylinder along {} r = {radius}", axis_name(*axis))
        }
        SolidSpec::Torus {
            axis, major, minor, ..
        } => format!("Torus about {} R = {major}, r = {minor}", axis_name(*axis)),
        SolidSpec::Halfplane { .. } => "Half-plane".into(),
        SolidSpec::Halfspace { .. } => "Half-space".into(),
        SolidSpec::Union { .. } => "Union".into(),
        SolidSpec::Intersection { .. } => "Intersection".into(),
        SolidSpec::Difference { .. } => "Difference".into(),
        SolidSpec::BlendUnion { a0, .. } => format!("Blended union a0 = {a0}"),
        SolidSpec::BlendIntersection { a0, .. } => format!("Blended intersection a0 = {a0}"),
        SolidSpec::Morph { t, .. } => format!("Morph t = {t}"),
        SolidSpec::Transform { .. } => "Transform".into(),
        SolidSpec::Part { name, hidden, .. } => {
            let name = if name.is_empty() {
                "Unnamed part".to_owned()
            } else {
                format!("“{name}”")
            };
            if *hidden {
                format!("{name} (hidden)")
            } else {
                name
            }
        }
        SolidSpec::Esc { .. } => "Free-form model".into(),
        SolidSpec::Plasm { .. } => "Script".into(),
        SolidSpec::Hyperfun { .. } => "HyperFun program".into(),
        SolidSpec::Piecewise { cells, degree, .. } => {
            let what = if cells.len() == 3 { "volume" } else { "patch" };
            let join = |x: &[usize]| {
                x.iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(" × ")
            };
            format!(
                "Piecewise {what}: {} cells of degree {}",
                join(cells),
                join(degree)
            )
        }
    }
}

fn axis_name(axis: CoordAxis) -> &'static str {
    ["x", "y", "z"][axis.index()]
}

impl Outline {
    /// The outline of `root`, its root selected.
    ///
    /// # Errors
    ///
    /// A tree that breaks a rule of DESIGN §5.
    pub fn new(root: SolidSpec) -> Result<Self, Error> {
        let dim = match ModelFile::from_spec(root.clone()).to_tree()? {
            ModelTree::Plane(_) => 2,
            ModelTree::Space(_) => 3,
        };
        Ok(Self {
            root,
            dim,
            selected: Vec::new(),
        })
    }

    /// The tree.
    #[must_use]
    pub fn root(&self) -> &SolidSpec {
        &self.root
    }

    /// 2 or 3.
    #[must_use]
    pub fn dimension(&self) -> usize {
        self.dim
    }

    /// The selected node's path.
    #[must_use]
    pub fn selected(&self) -> &[usize] {
        &self.selected
    }

    /// The node at `path`.
    #[must_use]
    pub fn node(&self, path: &[usize]) -> Option<&SolidSpec> {
        path.iter()
            .try_fold(&self.root, |spec, &i| spec.children().get(i))
    }

    /// Selects the node at `path`.
    ///
    /// # Errors
    ///
    /// When there is no such node.
    pub fn select(&mut self, path: &[usize]) -> Result<(), Error> {
        self.node(path)
            .ok_or_else(|| Error::new("there is no such node"))?;
        self.selected = path.to_vec();
        Ok(())
    }

    /// The outliner's rows, depth first.
    #[must_use]
    pub fn rows(&self) -> Vec<Row> {
        let mut out = Vec::new();
        let mut todo = vec![(Vec::new(), &self.root, false)];
        while let Some((path, spec, under_hidden)) = todo.pop() {
            let hidden = under_hidden || matches!(spec, SolidSpec::Part { hidden: true, .. });
            out.push(Row {
                depth: path.len(),
                label: label(spec),
                bezier: crate::document::editable(spec),
                hidden,
                path: path.clone(),
            });
            for (i, child) in spec.children().iter().enumerate().rev() {
                let mut p = path.clone();
                p.push(i);
                todo.push((p, child, hidden));
            }
        }
        out
    }

    /// Replaces the tree by `root` with `selected` selected, if `root` is a valid tree.
    fn commit(&mut self, root: SolidSpec, selected: NodePath) -> Result<(), Error> {
        // A root replaced whole may be of the other dimension.
        self.dim = match ModelFile::from_spec(root.clone()).to_tree()? {
            ModelTree::Plane(_) => 2,
            ModelTree::Space(_) => 3,
        };
        self.root = root;
        self.selected = selected;
        Ok(())
    }

    fn node_mut<'a>(root: &'a mut SolidSpec, path: &[usize]) -> Option<&'a mut SolidSpec> {
        let mut spec = root;
        for &i in path {
            spec = spec.child_mut(i)?;
        }
        Some(spec)
    }

    /// A new node of `kind`, centred at `at` (the tree's dimension).
    fn make(&self, kind: NewNode, at: DVec3) -> Result<SolidSpec, Error> {
        let d2 = self.dim == 2;
        Ok(match (kind, d2) {
            (NewNode::Sphere, false) => SolidSpec::Sphere {
                center: at.to_array(),
                radius: 0.4,
            },
            (NewNode::Sphere, true) => SolidSpec::Circle {
                center: at.truncate().to_array(),
                radius: 0.4,
            },
            (NewNode::Box, false) => SolidSpec::Box {
                min: (at - 0.3).to_array(),
                max: (at + 0.3).to_array(),
            },
            (NewNode::Box, true) => SolidSpec::Rectangle {
                min: (at.truncate() - 0.3).to_array(),
                max: (at.truncate() + 0.3).to_array(),
            },
            (NewNode::Cylinder, false) => SolidSpec::Cylinder {
                center: at.to_array(),
                axis: CoordAxis::Z,
                radius: 0.25,
            },
            (NewNode::Torus, false) => SolidSpec::Torus {
                center: at.to_array(),
                axis: CoordAxis::Z,
                major: 0.4,
                minor: 0.12,
            },
            (NewNode::Half, false) => SolidSpec::Halfspace {
                normal: [0.0, 0.0, 1.0],
                offset: at.z,
            },
            (NewNode::Half, true) => SolidSpec::Halfplane {
                normal: [0.0, 1.0],
                offset: at.y,
            },
            (NewNode::Bezier, false) => {
                let lo = at - 0.5;
                let v = Solid3::regular([3, 3, 3], lo, lo + 1.0, |[i, j, k]| {
                    let d = |a: usize| (a as f64 - 1.5).abs();
                    0.3 - 0.15 * (d(i) + d(j) + d(k))
                })?;
                ModelFile::from_solid3(&v).solid
            }
            (NewNode::Bezier, true) => {
                let lo = at.truncate() - 0.5;
                let v = Solid2::regular([3, 3], lo, lo + DVec2::ONE, |[i, j]| {
                    let d = |a: usize| (a as f64 - 1.5).abs();
                    0.3 - 0.2 * (d(i) + d(j))
                })?;
                ModelFile::from_solid2(&v).solid
            }
            (NewNode::Hyperfun, false) => SolidSpec::Hyperfun {
                program: hyperfun_part(at),
                bounds: Some([(at - 0.8).to_array(), (at + 0.8).to_array()]),
            },
            (NewNode::Cylinder | NewNode::Torus, true) => {
                return Err(Error::new("cylinders and tori are 3D: this tree is 2D"));
            }
            (NewNode::Hyperfun, true) => {
                return Err(Error::new("HyperFun programs are 3D: this tree is 2D"));
            }
        })
    }

    /// Adds a node of `kind` at `at` (see the module documentation); it is selected.
    ///
    /// # Errors
    ///
    /// A kind of the other dimension, or a tree past the caps.
    pub fn add(&mut self, kind: NewNode, at: DVec3) -> Result<(), Error> {
        let node = self.make(kind, at)?;
        let mut root = self.root.clone();
        let sel = self.selected.clone();
        // The selection's operation when it is not one itself: a part added beside a part joins
        // their union (or intersection, or difference).
        let parent_joins = self.node(&sel).is_some_and(|n| {
            !matches!(
                n,
                SolidSpec::Union { .. }
                    | SolidSpec::Intersection { .. }
                    | SolidSpec::Difference { .. }
            )
        }) && sel.split_last().is_some_and(|(_, up)| {
            matches!(
                self.node(up),
                Some(
                    SolidSpec::Union { .. }
                        | SolidSpec::Intersection { .. }
                        | SolidSpec::Difference { .. }
                )
            )
        });
        let sel = if parent_joins {
            sel[..sel.len() - 1].to_vec()
        } else {
            sel
        };
        let target =
            Self::node_mut(&mut root, &sel).ok_or_else(|| Error::new("there is no such node"))?;
        let path = if let Some(of) = variadic_mut(target) {
            of.push(node);
            let mut p = sel.clone();
            p.push(of.len() - 1);
            p
        } else {
            let old = core::mem::replace(target, SolidSpec::Union { of: Vec::new() });
            *target = SolidSpec::Union {
                of: vec![old, node],
            };
            let mut p = sel.clone();
            p.push(1);
            p
        };
        self.commit(root, path)
    }

    /// Puts `op` around the selected node (see the module documentation); the new operation is
    /// selected.
    ///
    /// # Errors
    ///
    /// A tree past the caps.
    pub fn wrap(&mut self, op: Wrap, at: DVec3) -> Result<(), Error> {
        let second = self.make(NewNode::Sphere, at + DVec3::new(0.3, 0.0, 0.0))?;
        let mut root = self.root.clone();
        let sel = self.selected.clone();
        let target =
            Self::node_mut(&mut root, &sel).ok_or_else(|| Error::new("there is no such node"))?;
        let x = core::mem::replace(target, SolidSpec::Union { of: Vec::new() });
        let two = vec![x.clone(), second];
        *target = match op {
            Wrap::Union => SolidSpec::Union { of: two },
            Wrap::Intersection => SolidSpec::Intersection { of: two },
            Wrap::Difference => SolidSpec::Difference { of: two },
            Wrap::BlendUnion => SolidSpec::BlendUnion {
                of: two,
                a0: 0.1,
                a1: 1.0,
                a2: 1.0,
            },
            Wrap::BlendIntersection => SolidSpec::BlendIntersection {
                of: two,
                a0: 0.1,
                a1: 1.0,
                a2: 1.0,
            },
            Wrap::Morph => SolidSpec::Morph { of: two, t: 0.5 },
            Wrap::Transform => SolidSpec::Transform {
                solid: Box::new(x),
                translate: Some(vec![0.0; self.dim]),
                rotate: Some(if self.dim == 2 {
                    Rotation::Angle(0.0)
                } else {
                    Rotation::Angles([0.0; 3])
                }),
                scale: Some(vec![1.0; self.dim]),
            },
        };
        self.commit(root, sel)
    }

    /// Removes the selected node (see the module documentation); its parent is selected.
    ///
    /// # Errors
    ///
    /// For the root: a model keeps one solid.
    pub fn remove(&mut self) -> Result<(), Error> {
        let Some((&last, parent_path)) = self.selected.split_last() else {
            return Err(Error::new(
                "the root stays: a model holds at least one solid",
            ));
        };
        if matches!(
            self.node(parent_path),
            Some(SolidSpec::Transform { .. } | SolidSpec::Part { .. })
        ) {
            // A transform or a named part without its solid goes too.
            let mut up = self.clone();
            up.selected = parent_path.to_vec();
            up.remove()?;
            *self = up;
            return Ok(());
        }
        let mut root = self.root.clone();
        let parent = Self::node_mut(&mut root, parent_path)
            .ok_or_else(|| Error::new("there is no such node"))?;
        let of = parent
            .operands_mut()
            .ok_or_else(|| Error::new("there is no such node"))?;
        if last < of.len() {
            of.remove(last);
        }
        // An operation of one operand is that operand.
        if let Some(only) = (of.len() == 1).then(|| of.remove(0)) {
            *parent = only;
        }
        self.commit(root, parent_path.to_vec())
    }

    /// Moves the selected node `by` places among its siblings (clamped to the ends).
    ///
    /// # Errors
    ///
    /// A tree that breaks a rule (none: an order changes only values).
    pub fn reorder(&mut self, by: isize) -> Result<(), Error> {
        let Some((&last, parent_path)) = self.selected.split_last() else {
            return Ok(());
        };
        let mut root = self.root.clone();
        let Some(parent) = Self::node_mut(&mut root, parent_path) else {
            return Ok(());
        };
        let Some(of) = parent.operands_mut() else {
            return Ok(());
        };
        let to = last
            .saturating_add_signed(by)
            .min(of.len().saturating_sub(1));
        let node = of.remove(last);
        of.insert(to, node);
        let mut selected = parent_path.to_vec();
        selected.push(to);
        self.commit(root, selected)
    }

    /// The numbers of the selected node that [`Self::set`] takes, with their values, in the order
    /// a panel lists them.
    #[must_use]
    pub fn fields(&self) -> Vec<(String, f64)> {
        let Some(node) = self.node(&self.through_parts(&self.selected)) else {
            return Vec::new();
        };
        let each = |name: &str, v: &[f64]| -> Vec<(String, f64)> {
            v.iter()
                .enumerate()
                .map(|(i, &x)| (format!("{name}[{i}]"), x))
                .collect()
        };
        let one = |name: &str, v: f64| vec![(name.to_owned(), v)];
        match node {
            SolidSpec::Circle { center, radius } => {
                [each("center", center), one("radius", *radius)].concat()
            }
            SolidSpec::Sphere { center, radius } | SolidSpec::Cylinder { center, radius, .. } => {
                [each("center", center), one("radius", *radius)].concat()
            }
            SolidSpec::Rectangle { min, max } => [each("min", min), each("max", max)].concat(),
            SolidSpec::Box { min, max } => [each("min", min), each("max", max)].concat(),
            SolidSpec::Torus {
                center,
                major,
                minor,
                ..
            } => [
                each("center", center),
                one("major", *major),
                one("minor", *minor),
            ]
            .concat(),
            SolidSpec::Halfplane { normal, offset } => {
                [each("normal", normal), one("offset", *offset)].concat()
            }
            SolidSpec::Halfspace { normal, offset } => {
                [each("normal", normal), one("offset", *offset)].concat()
            }
            SolidSpec::BlendUnion { a0, a1, a2, .. }
            | SolidSpec::BlendIntersection { a0, a1, a2, .. } => {
                [one("a0", *a0), one("a1", *a1), one("a2", *a2)].concat()
            }
            SolidSpec::Morph { t, .. } => one("t", *t),
            SolidSpec::Transform {
                translate,
                rotate,
                scale,
                ..
            } => {
                let d = self.dim;
                let translate = translate.clone().unwrap_or_else(|| vec![0.0; d]);
                let scale = scale.clone().unwrap_or_else(|| vec![1.0; d]);
                let rotate = match rotate {
                    Some(Rotation::Angle(a)) => one("rotate", *a),
                    Some(Rotation::Angles(a)) => each("rotate", a),
                    None if d == 2 => one("rotate", 0.0),
                    None => each("rotate", &[0.0; 3]),
                };
                [each("translate", &translate), rotate, each("scale", &scale)].concat()
            }
            _ => Vec::new(),
        }
    }

    /// The node a named part stands for: `path`, or through the parts at it to their solid.
    #[must_use]
    pub fn through_parts(&self, path: &[usize]) -> NodePath {
        let mut path = path.to_vec();
        while let Some(SolidSpec::Part { .. }) = self.node(&path) {
            path.push(0);
        }
        path
    }

    /// Names the selection (a part around it, or its name changed; an empty name on a shown part
    /// takes the part away). The part is selected.
    ///
    /// # Errors
    ///
    /// A name past [`bezsolid_core::model::MAX_NAME_BYTES`].
    pub fn rename(&mut self, name: &str) -> Result<(), Error> {
        self.relabel(|n, _| *n = name.trim().to_owned())
    }

    /// Hides the selection from the views, or shows it again (a part around it, or its flag
    /// turned; a shown part without a name is taken away). The part is selected.
    ///
    /// # Errors
    ///
    /// None in practice.
    pub fn toggle_hidden(&mut self) -> Result<(), Error> {
        self.relabel(|_, h| *h = !*h)
    }

    fn relabel(&mut self, change: impl FnOnce(&mut String, &mut bool)) -> Result<(), Error> {
        let mut root = self.root.clone();
        let sel = self.selected.clone();
        let node =
            Self::node_mut(&mut root, &sel).ok_or_else(|| Error::new("there is no such node"))?;
        let old = core::mem::replace(node, SolidSpec::Union { of: Vec::new() });
        let (solid, mut name, mut hidden) = match old {
            SolidSpec::Part {
                solid,
                name,
                hidden,
            } => (solid, name, hidden),
            other => (Box::new(other), String::new(), false),
        };
        change(&mut name, &mut hidden);
        *node = if name.is_empty() && !hidden {
            *solid
        } else {
            SolidSpec::Part {
                solid,
                name,
                hidden,
            }
        };
        self.commit(root, sel)
    }

    /// The selected node past any named parts around it, and its path: the node a part's
    /// numbers or program are of.
    #[must_use]
    pub fn selected_leaf(&self) -> Option<(Vec<usize>, &SolidSpec)> {
        let mut path = self.selected.clone();
        let mut node = self.node(&path)?;
        while let SolidSpec::Part { solid, .. } = node {
            path.push(0);
            node = solid;
        }
        Some((path, node))
    }

    /// Replaces the node at `path` by `node` (the selection stays).
    ///
    /// # Errors
    ///
    /// No such node, or a tree that breaks a rule.
    pub fn replace(&mut self, path: &[usize], node: SolidSpec) -> Result<(), Error> {
        let mut root = self.root.clone();
        let slot =
            Self::node_mut(&mut root, path).ok_or_else(|| Error::new("there is no such node"))?;
        *slot = node;
        let selected = self.selected.clone();
        self.commit(root, selected)
    }

    /// Sets the number `field` of the selected node: `radius`, `major`, `minor`, `offset`, `a0`,
    /// `a1`, `a2`, `t`, or an element `center[i]`, `min[i]`, `max[i]`, `normal[i]`,
    /// `translate[i]`, `rotate[i]` (`rotate` alone in 2D), `scale[i]`.
    ///
    /// # Errors
    ///
    /// A field the node does not have, or a value the tree's rules refuse (a zero radius, …).
    pub fn set(&mut self, field: &str, value: f64) -> Result<(), Error> {
        let (name, index) = match field.split_once('[') {
            Some((name, rest)) => {
                let i = rest
                    .strip_suffix(']')
                    .and_then(|i| i.parse::<usize>().ok())
                    .ok_or_else(|| Error::new(format!("no field {field:?}")))?;
                (name, Some(i))
            }
            None => (field, None),
        };
        let dim = self.dim;
        let mut root = self.root.clone();
        let sel = self.selected.clone();
        let node = Self::node_mut(&mut root, &self.through_parts(&sel))
            .ok_or_else(|| Error::new("there is no such node"))?;
        let missing = || Error::new(format!("this node has no {field:?}"));
        let slot: &mut f64 = match (node, name, index) {
            (
                SolidSpec::Circle { radius, .. }
                | SolidSpec::Sphere { radius, .. }
                | SolidSpec::Cylinder { radius, .. },
                "radius",
                None,
            ) => radius,
            (SolidSpec::Torus { major, .. }, "major", None) => major,
            (SolidSpec::Torus { minor, .. }, "minor", None) => minor,
            (
                SolidSpec::Halfplane { offset, .. } | SolidSpec::Halfspace { offset, .. },
                "offset",
                None,
            ) => offset,
            (
                SolidSpec::BlendUnion { a0, a1, a2, .. }
                | SolidSpec::BlendIntersection { a0, a1, a2, .. },
                a,
                None,
            ) => match a {
                "a0" => a0,
                "a1" => a1,
                "a2" => a2,
                _ => return Err(missing()),
            },
            (SolidSpec::Morph { t, .. }, "t", None) => t,
            (SolidSpec::Circle { center, .. }, "center", Some(i)) => {
                center.get_mut(i).ok_or_else(missing)?
            }
            (
                SolidSpec::Sphere { center, .. }
                | SolidSpec::Cylinder { center, .. }
                | SolidSpec::Torus { center, .. },
                "center",
                Some(i),
            ) => center.get_mut(i).ok_or_else(missing)?,
            (SolidSpec::Rectangle { min, .. }, "min", Some(i)) => {
                min.get_mut(i).ok_or_else(missing)?
            }
            (SolidSpec::Rectangle { max, .. }, "max", Some(i)) => {
                max.get_mut(i).ok_or_else(missing)?
            }
            (SolidSpec::Box { min, .. }, "min", Some(i)) => min.get_mut(i).ok_or_else(missing)?,
            (SolidSpec::Box { max, .. }, "max", Some(i)) => max.get_mut(i).ok_or_else(missing)?,
            (SolidSpec::Halfplane { normal, .. }, "normal", Some(i)) => {
                normal.get_mut(i).ok_or_else(missing)?
            }
            (SolidSpec::Halfspace { normal, .. }, "normal", Some(i)) => {
                normal.get_mut(i).ok_or_else(missing)?
            }
            (SolidSpec::Transform { translate, .. }, "translate", Some(i)) => translate
                .get_or_insert_with(|| vec![0.0; dim])
                .get_mut(i)
                .ok_or_else(missing)?,
            (SolidSpec::Transform { scale, .. }, "scale", Some(i)) => scale
                .get_or_insert_with(|| vec![1.0; dim])
                .get_mut(i)
                .ok_or_else(missing)?,
            (SolidSpec::Transform { rotate, .. }, "rotate", i) => match (
                rotate.get_or_insert(if dim == 2 {
                    Rotation::Angle(0.0)
                } else {
                    Rotation::Angles([0.0; 3])
                }),
                i,
            ) {
                (Rotation::Angle(a), None) => a,
                (Rotation::Angles(a), Some(i)) => a.get_mut(i).ok_or_else(missing)?,
                _ => return Err(missing()),
            },
            _ => return Err(missing()),
        };
        *slot = value;
        self.commit(root, sel)
    }
}

/// The program of a new HyperFun part at `at`: a ball blended with a torus, as HyperFun's
/// library writes them.
fn hyperfun_part(at: DVec3) -> String {
    format!(
        "-- A ball blended with a ring: edit it in the HyperFun mode.\n\
         my_model(x[3], a[1])\n{{\n  array centre[3];\n  centre = [{}, {}, {}];\n  \
         ball = hfSphere(x, centre, 0.35);\n  ring = hfTorusZ(x, centre, 0.5, 0.12);\n  \
         my_model = hfBlendUni(ball, ring, 0.05, 1, 1);\n}}\n",
        at.x, at.y, at.z
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn tree3(o: &Outline) -> bezsolid_core::tree::Tree<3> {
        match ModelFile::from_spec(o.root().clone()).to_tree().unwrap() {
            ModelTree::Space(t) => t,
            ModelTree::Plane(_) => panic!("2D"),
        }
    }

    /// A model built from scratch as the outliner builds it: a volume, a sphere beside it, a
    /// union, a blend, a move, a number typed, a node removed.
    #[test]
    fn a_model_is_built_node_by_node() {
        let volume = {
            let mut o = Outline::new(SolidSpec::Sphere {
                center: [0.0; 3],
                radius: 1.0,
            })
            .unwrap();
            o.add(NewNode::Bezier, DVec3::new(2.0, 0.0, 0.0)).unwrap();
            o.node(o.selected()).unwrap().clone()
        };
        let mut o = Outline::new(volume).unwrap();
        assert_eq!(o.dimension(), 3);
        o.add(NewNode::Sphere, DVec3::new(0.6, 0.0, 0.0)).unwrap();
        assert_eq!(o.selected(), [1]);
        assert!(matches!(o.root(), SolidSpec::Union { of } if of.len() == 2));
        // A box joins the union, then the sphere is blended with a small sphere and moved.
        o.select(&[]).unwrap();
        o.add(NewNode::Box, DVec3::new(0.0, 1.0, 0.0)).unwrap();
        assert_eq!(o.selected(), [2]);
        o.select(&[1]).unwrap();
        o.wrap(Wrap::BlendUnion, DVec3::new(0.6, 0.0, 0.0)).unwrap();
        o.set("a0", 0.2).unwrap();
        o.wrap(Wrap::Transform, DVec3::ZERO).unwrap();
        o.set("translate[2]", 0.5).unwrap();
        o.set("rotate[1]", 30.0).unwrap();
        let rows = o.rows();
        let labels: Vec<&str> = rows.iter().map(|r| r.label.as_str()).collect();
        assert_eq!(labels[0], "Union");
        assert!(
            labels[1].starts_with("Bézier volume 4 × 4 × 4"),
            "{labels:?}"
        );
        assert_eq!(labels[2], "Transform");
        assert!(
            labels[3].starts_with("Blended union a0 = 0.2"),
            "{labels:?}"
        );
        assert_eq!(rows[4].depth, 3);
        assert!(rows[1].bezier && !rows[2].bezier);
        // The moved blend: the sphere's centre (0.6, 0, 0), moved up by 0.5 (the rotation about y
        // turns it first).
        let t = tree3(&o);
        let c = glam::DMat3::from_rotation_y(30f64.to_radians()) * DVec3::new(0.6, 0.0, 0.0)
            + DVec3::new(0.0, 0.0, 0.5);
        assert!(t.f(c) > 0.0);
        // Bad values are refused and change nothing.
        let before = o.clone();
        assert!(o.set("scale[0]", 0.0).is_err());
        assert!(o.set("radius", 1.0).is_err(), "a transform has no radius");
        assert_eq!(o, before);
        // Removing the box leaves a union of two; removing the volume leaves the transform alone.
        o.select(&[2]).unwrap();
        o.remove().unwrap();
        assert!(matches!(o.root(), SolidSpec::Union { of } if of.len() == 2));
        o.select(&[0]).unwrap();
        o.remove().unwrap();
        assert!(matches!(o.root(), SolidSpec::Transform { .. }));
        o.select(&[]).unwrap();
        assert!(o.remove().is_err(), "the root stays");
        // The solid of the root transform goes only with the transform, which is the root: it
        // stays, and so does the selection.
        o.select(&[0]).unwrap();
        let before = o.clone();
        assert!(o.remove().is_err());
        assert_eq!(o, before);
    }

    /// Names and hiding: a part around the selection, its numbers set through it, the rows say
    /// so, and a shown part without a name goes away.
    #[test]
    fn nodes_are_named_and_hidden() {
        let mut o = Outline::new(SolidSpec::Sphere {
            center: [0.0; 3],
            radius: 1.0,
        })
        .unwrap();
        o.add(NewNode::Box, DVec3::X).unwrap();
        o.rename("  lid ").unwrap();
        assert!(
            matches!(o.node(&[1]), Some(SolidSpec::Part { name, hidden: false, .. }) if name == "lid")
        );
        o.set("max[2]", 0.5).unwrap();
        assert!(matches!(o.node(&[1, 0]), Some(SolidSpec::Box { max, .. }) if max[2] == 0.5));
        assert_eq!(o.fields().len(), 6, "the box's numbers");
        o.toggle_hidden().unwrap();
        let rows = o.rows();
        assert_eq!(rows[2].label, "“lid” (hidden)");
        assert!(rows[2].hidden && rows[3].hidden && !rows[1].hidden);
        assert!(o.rename(&"x".repeat(300)).is_err(), "a name past the cap");
        o.rename("").unwrap();
        assert_eq!(o.rows()[2].label, "Unnamed part (hidden)");
        o.toggle_hidden().unwrap();
        assert!(
            matches!(o.node(&[1]), Some(SolidSpec::Box { .. })),
            "no name, shown: no part"
        );
    }

    #[test]
    fn nodes_reorder_and_kinds_keep_to_the_dimension() {
        let mut o = Outline::new(SolidSpec::Circle {
            center: [0.0, 0.0],
            radius: 1.0,
        })
        .unwrap();
        assert_eq!(o.dimension(), 2);
        o.wrap(Wrap::Difference, DVec3::ZERO).unwrap();
        o.add(NewNode::Box, DVec3::new(0.5, 0.5, 0.0)).unwrap();
        assert!(o.add(NewNode::Torus, DVec3::ZERO).is_err());
        o.select(&[2]).unwrap();
        o.reorder(-5).unwrap();
        assert_eq!(o.selected(), [0]);
        assert!(matches!(o.node(&[0]), Some(SolidSpec::Rectangle { .. })));
        o.add(NewNode::Bezier, DVec3::ZERO).unwrap();
        assert!(
            o.rows()
                .iter()
                .any(|r| r.bezier && r.label.starts_with("Bézier patch 4 × 4"))
        );
        assert!(o.select(&[7]).is_err());
    }
}
