//! HyperFun export of a tree of many solids: one `my_model` whose body computes every node in turn,
//! with HyperFun's own set operations (`|`, `&`, `\`, which it defines as the R-functions of
//! DESIGN §5), its blends `hfBlendUni` and `hfBlendInt` (`(f1 | f2)` or `(f1 & f2)` plus
//! `a0 / (1 + (f1/a1)² + (f2/a2)²)`), its primitives `hfSphere` and `hfCylinderX/Y/Z` (whose
//! definitions are DESIGN's sphere and cylinder), and plain arithmetic for the rest: boxes,
//! tori, half-spaces, morphs, 2D primitives, and regular Bézier leaves as the explicit Bernstein
//! sum of a single solid's export; a HyperFun leaf's program as bodies of their own before
//! `my_model` (renamed apart), called on its coordinates and cut by its box. A transform's node
//! sees its own coordinates, an array
//! `M⁻¹ x` computed from its parent's. Every operand is parenthesised, so the file means the
//! same whatever the precedence of the set operations. 2D trees are prisms along z (`x[3]`
//! unused).

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::{self, Write as _};

use super::mapped::{self, MappedLeaf, mapped_leaf, mapped_net, write_mapped};
use super::{basis_term, num, over};
use crate::model::{CoordAxis, ModelError, ModelFile, Rotation, SolidSpec};
use crate::solid::Solid;
use crate::tree::ModelTree;

/// Why a tree has no HyperFun export.
#[derive(Clone, Debug, PartialEq)]
pub enum TreeHfError {
    /// The model is not a valid tree.
    Model(ModelError),
    /// The export would write more numbers than [`MAX_NUMBERS`] (the space-mapped leaves' nets and
    /// seed tables): the path of the leaf that passed it and the count so far.
    TooLarge {
        /// The leaf's path in the tree.
        path: String,
        /// The numbers the export had written with it.
        numbers: usize,
    },
}

/// The most numbers one export writes in the arrays of its space-mapped leaves (about 20 MB of
/// text).
pub const MAX_NUMBERS: usize = 1 << 20;

impl fmt::Display for TreeHfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Model(e) => e.fmt(f),
            Self::TooLarge { path, numbers } => write!(
                f,
                "{path}: the HyperFun export of this model's space-mapped solids would write \
                 {numbers} numbers, more than the {MAX_NUMBERS} it writes at most"
            ),
        }
    }
}

impl core::error::Error for TreeHfError {}

/// The HyperFun model of a model file's tree (a single patch or volume too).
///
/// # Errors
///
/// [`TreeHfError`]: an invalid tree, or one whose space-mapped leaves pass [`MAX_NUMBERS`].
pub fn tree_hf(file: &ModelFile) -> Result<String, TreeHfError> {
    tree_hf_within(file, MAX_NUMBERS)
}

/// [`tree_hf`] writing at most `cap` numbers for space-mapped leaves.
fn tree_hf_within(file: &ModelFile, cap: usize) -> Result<String, TreeHfError> {
    let dim = match file.to_tree().map_err(TreeHfError::Model)? {
        ModelTree::Plane(_) => 2,
        ModelTree::Space(_) => 3,
    };
    let mut w = Writer {
        dim,
        body: String::new(),
        bodies: String::new(),
        arrays: Vec::new(),
        next: 0,
        numbers: 0,
        cap,
    };
    let root = w.node(&file.solid, "solid", "x")?;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "-- A model of many solids ({dim}D), exported by bezsolid: every node of the tree in turn."
    );
    if dim == 2 {
        let _ = writeln!(out, "-- A 2D model: x[3] is unused (a prism along z).");
    }
    out.push_str(&w.bodies);
    let _ = writeln!(out, "my_model(x[3], a[1])\n{{");
    for (name, len) in &w.arrays {
        let _ = writeln!(out, "  array {name}[{len}];");
    }
    out.push_str(&w.body);
    let _ = writeln!(out, "  my_model = {root};\n}}");
    #[cfg(feature = "link")]
    let out = super::with_model(&out, file);
    Ok(out)
}

struct Writer {
    dim: usize,
    body: String,
    /// The bodies of HyperFun leaves, renamed, written before `my_model`.
    bodies: String,
    /// Arrays to declare: name and length.
    arrays: Vec<(String, usize)>,
    next: usize,
    /// The numbers the space-mapped leaves' arrays hold so far.
    numbers: usize,
    /// The most they may hold.
    cap: usize,
}

impl Writer {
    fn name(&mut self, prefix: &str) -> String {
        self.next += 1;
        format!("{prefix}{}", self.next)
    }

    /// `value` in a new variable; its name.
    fn set(&mut self, what: &str, value: &str) -> String {
        let name = self.name("n");
        let _ = writeln!(self.body, "  -- {what}\n  {name} = {value};");
        name
    }

    /// An array holding `values`; its name.
    fn array(&mut self, prefix: &str, values: &[f64]) -> String {
        let name = self.name(prefix);
        self.arrays.push((name.clone(), 3));
        // A whole array's items are bare signed numbers in HyperFun's grammar (`-0.5`, not `(-0.5)`).
        let mut v: Vec<String> = values.iter().map(|&x| format!("{x}")).collect();
        v.resize(3, String::from("0"));
        let _ = writeln!(self.body, "  {name} = [{}];", v.join(", "));
        name
    }

    /// `(q[i] - c)²` as a product.
    fn square_off(q: &str, i: usize, c: f64) -> String {
        format!("(({q}[{i}] - {c}) * ({q}[{i}] - {c}))", c = num(c))
    }

    /// The variable of node `spec` at `path`, in the coordinates of array `q`.
    fn node(&mut self, spec: &SolidSpec, path: &str, q: &str) -> Result<String, TreeHfError> {
        Ok(match spec {
            SolidSpec::Sphere { center, radius } => {
                let c = self.array("c", center);
                self.set(path, &format!("hfSphere({q}, {c}, {})", num(*radius)))
            }
            SolidSpec::Circle { center, radius } => {
                let terms: Vec<String> = (0..2)
                    .map(|i| Self::square_off(q, i + 1, center[i]))
                    .collect();
                let r = num(*radius);
                self.set(path, &format!("{r} * {r} - ({})", terms.join(" + ")))
            }
            SolidSpec::Box { min, max } => self.cuboid(path, q, min, max),
            SolidSpec::Rectangle { min, max } => self.cuboid(path, q, min, max),
            SolidSpec::Cylinder {
                center,
                axis,
                radius,
            } => {
                let c = self.array("c", center);
                let name = ["X", "Y", "Z"][axis.index()];
                self.set(
                    path,
                    &format!("hfCylinder{name}({q}, {c}, {})", num(*radius)),
                )
            }
            SolidSpec::Torus {
                center,
                axis,
                major,
                minor,
            } => {
                let k = axis.index();
                let across: Vec<String> = (0..3)
                    .filter(|&i| i != k)
                    .map(|i| Self::square_off(q, i + 1, center[i]))
                    .collect();
                let ring = self.name("t");
                let _ = writeln!(
                    self.body,
                    "  {ring} = sqrt({}) - {};",
                    across.join(" + "),
                    num(*major)
                );
                let (m, along) = (num(*minor), Self::square_off(q, k + 1, center[k]));
                self.set(
                    &format!("{path} (torus about {})", axis_name(*axis)),
                    &format!("{m} * {m} - {ring} * {ring} - {along}"),
                )
            }
            SolidSpec::Halfspace { normal, offset } => self.half(path, q, normal, *offset),
            SolidSpec::Halfplane { normal, offset } => self.half(path, q, normal, *offset),
            SolidSpec::Union { of } => self.fold(path, q, of, "|")?,
            SolidSpec::Intersection { of } => self.fold(path, q, of, "&")?,
            SolidSpec::Difference { of } => self.fold(path, q, of, "\\")?,
            SolidSpec::BlendUnion { of, a0, a1, a2 }
            | SolidSpec::BlendIntersection { of, a0, a1, a2 } => {
                let f1 = self.node(&of[0], &format!("{path}.of[0]"), q)?;
                let f2 = self.node(&of[1], &format!("{path}.of[1]"), q)?;
                let call = if matches!(spec, SolidSpec::BlendUnion { .. }) {
                    "hfBlendUni"
                } else {
                    "hfBlendInt"
                };
                self.set(
                    path,
                    &format!(
                        "{call}({f1}, {f2}, {}, {}, {})",
                        num(*a0),
                        num(*a1),
                        num(*a2)
                    ),
                )
            }
            SolidSpec::Morph { of, t } => {
                let f1 = self.node(&of[0], &format!("{path}.of[0]"), q)?;
                let f2 = self.node(&of[1], &format!("{path}.of[1]"), q)?;
                let t = num(*t);
                self.set(path, &format!("(1 - {t}) * {f1} + {t} * {f2}"))
            }
            SolidSpec::Transform {
                solid,
                translate,
                rotate,
                scale,
            } => {
                let inner = self.inverse_coordinates(q, translate, rotate, scale);
                self.node(solid, &format!("{path}.solid"), &inner)?
            }
            // A name is for people: the solid as it is.
            SolidSpec::Part { solid, .. } => self.node(solid, &format!("{path}.solid"), q)?,
            SolidSpec::Patch { .. } | SolidSpec::Volume { .. } => self.bezier(spec, path, q)?,
            SolidSpec::Piecewise { .. } => self.piecewise(spec, path, q)?,
            SolidSpec::Hyperfun { program, bounds } => self.hyperfun(program, *bounds, path, q)?,
            SolidSpec::Esc { .. } | SolidSpec::Plasm { .. } => {
                unreachable!("refused by the tree's validation")
            }
        })
    }

    /// A HyperFun leaf: its bodies written before `my_model` under names of their own (each
    /// prefixed, so that two leaves' bodies and `my_model` never meet), its main body called on
    /// the leaf's coordinates and cut by its box as the tree cuts it.
    fn hyperfun(
        &mut self,
        text: &str,
        bounds: Option<[[f64; 3]; 2]>,
        path: &str,
        q: &str,
    ) -> Result<String, TreeHfError> {
        let program = super::read::Program::parse(text).map_err(|e| {
            TreeHfError::Model(ModelError::Tree(crate::tree::TreeError {
                path: format!("{path}.program"),
                message: format!("invalid HyperFun program: {e}"),
            }))
        })?;
        let prefix = format!("{}_", self.name("hf"));
        let names: Vec<&str> = program.body_names().collect();
        // The leaf's own carried model, if it is an export, is not this file's.
        let own: String = text
            .lines()
            .filter(|l| !l.trim_end().starts_with(super::MODEL_MARK))
            .map(|l| format!("{l}\n"))
            .collect();
        let _ = writeln!(
            self.bodies,
            "-- {path}: a HyperFun program, its bodies renamed"
        );
        self.bodies.push_str(&rename_bodies(&own, &names, &prefix));
        let [lo, hi] = bounds.unwrap_or(crate::model::DEFAULT_HYPERFUN_BOX);
        let call = format!("{prefix}{}({q}, a)", program.body());
        let cut = self.strips(q, &lo, &hi);
        Ok(self.set(path, &format!("({call}) & {cut}")))
    }

    fn cuboid(&mut self, path: &str, q: &str, min: &[f64], max: &[f64]) -> String {
        let value = self.strips(q, min, max);
        self.set(path, &value)
    }

    /// `s_0 & s_1 (& s_2)`, `s_i = (q_i − min_i)(max_i − q_i)`: a box's function.
    fn strips(&self, q: &str, min: &[f64], max: &[f64]) -> String {
        let strips: Vec<String> = (0..min.len())
            .map(|i| {
                format!(
                    "(({q}[{k}] - {lo}) * ({hi} - {q}[{k}]))",
                    k = i + 1,
                    lo = num(min[i]),
                    hi = num(max[i])
                )
            })
            .collect();
        strips
            .into_iter()
            .reduce(|a, b| format!("({a} & {b})"))
            .unwrap_or_default()
    }

    fn half(&mut self, path: &str, q: &str, normal: &[f64], offset: f64) -> String {
        let dot: Vec<String> = normal
            .iter()
            .enumerate()
            .map(|(i, &n)| format!("{} * {q}[{}]", num(n), i + 1))
            .collect();
        self.set(path, &format!("{} - ({})", num(offset), dot.join(" + ")))
    }

    fn fold(
        &mut self,
        path: &str,
        q: &str,
        of: &[SolidSpec],
        op: &str,
    ) -> Result<String, TreeHfError> {
        let mut names = Vec::with_capacity(of.len());
        for (i, child) in of.iter().enumerate() {
            names.push(self.node(child, &format!("{path}.of[{i}]"), q)?);
        }
        let value = names
            .into_iter()
            .reduce(|a, b| format!("({a} {op} {b})"))
            .unwrap_or_default();
        Ok(self.set(path, &value))
    }

    /// An array of the coordinates `M⁻¹ q` (`M = T · Rz · Ry · Rx · S`); its name.
    fn inverse_coordinates(
        &mut self,
        q: &str,
        translate: &Option<Vec<f64>>,
        rotate: &Option<Rotation>,
        scale: &Option<Vec<f64>>,
    ) -> String {
        let d = self.dim;
        let t: Vec<f64> = translate.clone().unwrap_or_else(|| alloc::vec![0.0; d]);
        let s: Vec<f64> = scale.clone().unwrap_or_else(|| alloc::vec![1.0; d]);
        let mut r = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        match rotate {
            Some(Rotation::Angle(a)) => {
                let (sin, cos) = crate::tree::sin_cos(*a);
                r[0][0] = cos;
                r[0][1] = -sin;
                r[1][0] = sin;
                r[1][1] = cos;
            }
            Some(Rotation::Angles(a)) => r = crate::tree::rotation3(*a),
            None => {}
        }
        let name = self.name("q");
        self.arrays.push((name.clone(), 3));
        // (M⁻¹ q)_i = (Σ_j R_ji (q_j − t_j)) / s_i.
        for i in 0..3 {
            let value = if i < d {
                let terms: Vec<String> = (0..d)
                    .map(|j| format!("{} * ({q}[{}] - {})", num(r[j][i]), j + 1, num(t[j])))
                    .collect();
                over(&terms.join(" + "), s[i])
            } else {
                format!("{q}[{}]", i + 1)
            };
            let _ = writeln!(self.body, "  {name}[{}] = {value};", i + 1);
        }
        name
    }

    /// A regular Bézier leaf: the explicit Bernstein sum, clipped to its box, in coordinates `q`.
    fn bezier(&mut self, spec: &SolidSpec, path: &str, q: &str) -> Result<String, TreeHfError> {
        let tree = ModelFile::from_spec(spec.clone())
            .to_tree()
            .map_err(TreeHfError::Model)?;
        let parts = match &tree {
            ModelTree::Plane(t) => regular_parts(t),
            ModelTree::Space(t) => regular_parts(t),
        };
        let Some(RegularLeaf { degree, lo, hi, xi }) = parts else {
            let (leaf, degree) = match &tree {
                ModelTree::Plane(t) => t
                    .as_solid()
                    .and_then(|s| Some((mapped_leaf(s)?, s.degree().to_vec()))),
                ModelTree::Space(t) => t
                    .as_solid()
                    .and_then(|s| Some((mapped_leaf(s)?, s.degree().to_vec()))),
            }
            .expect("a Bézier leaf is regular or space-mapped");
            return self.mapped(&leaf, &degree, path, q);
        };
        let tag = self.name("b");
        let mut params = Vec::new();
        for (k, &n) in degree.iter().enumerate() {
            let t = format!("{tag}{}", ["u", "v", "w"][k]);
            let _ = writeln!(
                self.body,
                "  {t} = {};",
                over(&format!("{q}[{}] - {}", k + 1, num(lo[k])), hi[k] - lo[k])
            );
            let _ = writeln!(self.body, "  {t}s = 1 - {t};");
            for i in 0..=n {
                let _ = writeln!(
                    self.body,
                    "  {t}{i} = {};",
                    basis_term(n, i, &t, &format!("{t}s"))
                );
            }
            params.push(t);
        }
        // Σ over the net in its index order, the last index fastest.
        let mut terms = Vec::with_capacity(xi.len());
        let mut index = alloc::vec![0usize; degree.len()];
        for &value in &xi {
            let factors: Vec<String> = index
                .iter()
                .enumerate()
                .map(|(k, &i)| format!("{}{i}", params[k]))
                .collect();
            terms.push(format!("{}*{}", factors.join("*"), num(value)));
            for k in (0..degree.len()).rev() {
                index[k] += 1;
                if index[k] <= degree[k] {
                    break;
                }
                index[k] = 0;
            }
        }
        let sum = self.name("s");
        let _ = writeln!(self.body, "  {sum} = {};", terms.join("\n    + "));
        let clip = params
            .iter()
            .map(|t| format!("({t}*{t}s)"))
            .reduce(|a, b| format!("({a} & {b})"))
            .unwrap_or_default();
        Ok(self.set(path, &format!("{sum} & {clip}")))
    }
}

impl Writer {
    /// Counts `leaf`'s numbers against [`MAX_NUMBERS`].
    fn count(&mut self, leaf: &MappedLeaf, path: &str) -> Result<(), TreeHfError> {
        self.numbers += leaf.numbers();
        if self.numbers > self.cap {
            return Err(TreeHfError::TooLarge {
                path: String::from(path),
                numbers: self.numbers,
            });
        }
        Ok(())
    }

    /// A space-mapped Bézier leaf in coordinates `q`: its inverse map written out.
    fn mapped(
        &mut self,
        leaf: &MappedLeaf,
        degree: &[usize],
        path: &str,
        q: &str,
    ) -> Result<String, TreeHfError> {
        self.count(leaf, path)?;
        let tag = self.name("m");
        let _ = writeln!(
            self.body,
            "  -- {path}: a space-mapped Bezier {} of degree ({})",
            if degree.len() == 2 { "patch" } else { "volume" },
            join(degree)
        );
        let code = write_mapped(leaf, &tag, q, None, &mut self.arrays);
        let f = code.single(&tag, &mut self.body);
        Ok(self.set(path, &f))
    }

    /// A piecewise leaf with moved points in coordinates `q`: every cell's preimages, the largest
    /// value over them (clipped on the global parameter), and with none the largest of the
    /// cells' continuations.
    fn piecewise_mapped(
        &mut self,
        cells: &[(Vec<usize>, MappedLeaf)],
        counts: &[usize],
        path: &str,
        q: &str,
    ) -> Result<String, TreeHfError> {
        let tag = self.name("m");
        let mut codes = Vec::with_capacity(cells.len());
        for (k, (at, leaf)) in cells.iter().enumerate() {
            self.count(leaf, path)?;
            let cell_tag = format!("{tag}c{k}x");
            let code = write_mapped(leaf, &cell_tag, q, Some((at, counts)), &mut self.arrays);
            self.body.push_str(&code.setup);
            codes.push(code);
        }
        let f = format!("{tag}f");
        let any = format!("{tag}any");
        let _ = writeln!(self.body, "  {any} = 0; {f} = 0;");
        for code in &codes {
            self.body.push_str(&code.search);
            let _ = writeln!(
                self.body,
                "  if ({} = 1) then\n    if ({any} = 0 or {} > {f}) then {f} = {}; endif;\n    \
                 {any} = 1;\n  endif;",
                code.found, code.best, code.best
            );
        }
        let _ = writeln!(
            self.body,
            "  -- No preimage in any cell: the largest continuation."
        );
        let _ = writeln!(self.body, "  if ({any} = 0) then");
        for (k, code) in codes.iter().enumerate() {
            self.body.push_str(&mapped::indent(&code.continuation, 2));
            let pick = if k == 0 {
                String::new()
            } else {
                format!(" or {} > {f}", code.cont)
            };
            let _ = writeln!(
                self.body,
                "    if ({any} = 0{pick}) then {f} = {}; endif;\n    {any} = 1;",
                code.cont
            );
        }
        let _ = writeln!(self.body, "  endif;");
        Ok(self.set(path, &f))
    }

    /// A regular piecewise leaf in coordinates `q`: the global parameters, each axis's cell
    /// (chosen by `if`s as `eval` chooses it: the last cell past the box, the first before it) and
    /// local parameter, the chosen cell's Bernstein sum, clipped by the global box.
    fn piecewise(&mut self, spec: &SolidSpec, path: &str, q: &str) -> Result<String, TreeHfError> {
        let tree = ModelFile::from_spec(spec.clone())
            .to_tree()
            .map_err(TreeHfError::Model)?;
        let regular = match &tree {
            ModelTree::Plane(t) => regular_cells(t),
            ModelTree::Space(t) => regular_cells(t),
        };
        let Some(leaf) = regular else {
            let (cells, counts) = match &tree {
                ModelTree::Plane(t) => moved_cells(t),
                ModelTree::Space(t) => moved_cells(t),
            }
            .expect("a piecewise leaf is regular or moved");
            return self.piecewise_mapped(&cells, &counts, path, q);
        };
        let tag = self.name("p");
        let d = leaf.cells.len();
        let _ = writeln!(
            self.body,
            "  -- {path}: piecewise, {} cells of degree ({})",
            leaf.cells
                .iter()
                .map(|c| alloc::format!("{c}"))
                .collect::<Vec<_>>()
                .join(" × "),
            leaf.degree
                .iter()
                .map(|c| alloc::format!("{c}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        let mut globals = Vec::new();
        let mut cells = Vec::new();
        let mut params = Vec::new();
        for k in 0..d {
            let axis = ["u", "v", "w"][k];
            let (g, t, c, u) = (
                format!("{tag}{axis}g"),
                format!("{tag}{axis}t"),
                format!("{tag}{axis}c"),
                format!("{tag}{axis}"),
            );
            let _ = writeln!(
                self.body,
                "  {g} = {};",
                over(
                    &format!("{q}[{}] - {}", k + 1, num(leaf.lo[k])),
                    leaf.hi[k] - leaf.lo[k]
                )
            );
            let _ = writeln!(self.body, "  {g}s = 1 - {g};");
            let _ = writeln!(self.body, "  {t} = {g} * {};", leaf.cells[k]);
            let _ = writeln!(self.body, "  {c} = 0;");
            for a in 1..leaf.cells[k] {
                let _ = writeln!(self.body, "  if ({t} >= {a}) then {c} = {a}; endif;");
            }
            let _ = writeln!(self.body, "  {u} = {t} - {c};");
            let _ = writeln!(self.body, "  {u}s = 1 - {u};");
            let n = leaf.degree[k];
            for i in 0..=n {
                let _ = writeln!(
                    self.body,
                    "  {u}{i} = {};",
                    basis_term(n, i, &u, &format!("{u}s"))
                );
            }
            globals.push(g);
            cells.push(c);
            params.push(u);
        }
        let sum = self.name("s");
        let dims: Vec<usize> = (0..d).map(|k| leaf.cells[k] * leaf.degree[k] + 1).collect();
        let count: usize = leaf.cells.iter().product();
        for flat in 0..count {
            // The cell's multi-index, the last axis fastest.
            let mut cell = alloc::vec![0usize; d];
            let mut rest = flat;
            for k in (0..d).rev() {
                cell[k] = rest % leaf.cells[k];
                rest /= leaf.cells[k];
            }
            let tests: Vec<String> = (0..d)
                .map(|k| format!("if ({} = {}) then", cells[k], cell[k]))
                .collect();
            let lens: Vec<usize> = leaf.degree.iter().map(|n| n + 1).collect();
            let terms: Vec<String> = (0..lens.iter().product())
                .map(|flat: usize| {
                    // The local index, the last axis fastest.
                    let mut local = alloc::vec![0usize; d];
                    let mut rest = flat;
                    for k in (0..d).rev() {
                        local[k] = rest % lens[k];
                        rest /= lens[k];
                    }
                    let g =
                        (0..d).fold(0, |g, k| g * dims[k] + cell[k] * leaf.degree[k] + local[k]);
                    let factors: Vec<String> = (0..d)
                        .map(|k| format!("{}{}", params[k], local[k]))
                        .collect();
                    format!("{}*{}", factors.join("*"), num(leaf.xi[g]))
                })
                .collect();
            let _ = writeln!(
                self.body,
                "  {} {sum} = {}; {}",
                tests.join(" "),
                terms.join("\n    + "),
                "endif; ".repeat(d).trim_end()
            );
        }
        let clip = globals
            .iter()
            .map(|g| format!("({g}*{g}s)"))
            .reduce(|a, b| format!("({a} & {b})"))
            .unwrap_or_default();
        Ok(self.set(path, &format!("{sum} & {clip}")))
    }
}

/// The cells of a piecewise leaf with moved points (their indices and nets) and the cell counts;
/// `None` for any other tree.
#[allow(clippy::type_complexity)]
fn moved_cells<const D: usize>(
    tree: &crate::tree::Tree<D>,
) -> Option<(Vec<(Vec<usize>, MappedLeaf)>, Vec<usize>)>
where
    crate::dim::Dim<D>: crate::dim::Dimension<D>,
{
    let s = tree.as_piecewise()?;
    let counts = s.cells();
    let total: usize = counts.iter().product();
    let cells = (0..total)
        .filter_map(|k| {
            let at = crate::tensor::multi_index(counts, k);
            let part = s.part(at)?;
            Some((at.to_vec(), mapped_net(part.net(), part.inverse())))
        })
        .collect();
    Some((cells, counts.to_vec()))
}

/// Numbers joined by commas.
fn join(values: &[usize]) -> String {
    values
        .iter()
        .map(|v| format!("{v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A regular piecewise leaf as its export needs it.
struct RegularCellsLeaf {
    cells: Vec<usize>,
    degree: Vec<usize>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// The global net's ξ, the last axis fastest.
    xi: Vec<f64>,
}

/// The leaf of a tree of one regular piecewise solid; `None` for one with moved points.
fn regular_cells<const D: usize>(tree: &crate::tree::Tree<D>) -> Option<RegularCellsLeaf>
where
    crate::dim::Dim<D>: crate::dim::Dimension<D>,
{
    let s = tree.as_piecewise()?;
    if !s.is_regular() {
        return None;
    }
    let (lo, hi) = s.domain();
    Some(RegularCellsLeaf {
        cells: s.cells().to_vec(),
        degree: s.degree().to_vec(),
        lo: <crate::dim::Dim<D> as crate::dim::Dimension<D>>::coords(lo).to_vec(),
        hi: <crate::dim::Dim<D> as crate::dim::Dimension<D>>::coords(hi).to_vec(),
        xi: s
            .points()
            .iter()
            .map(|&c| <crate::dim::Dim<D> as crate::dim::Dimension<D>>::split(c).1)
            .collect(),
    })
}

/// A regular Bézier leaf as its export needs it, whatever its dimension.
struct RegularLeaf {
    degree: Vec<usize>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    xi: Vec<f64>,
}

/// The leaf of a tree of one regular Bézier solid; `None` for a space mapping.
fn regular_parts<const D: usize>(tree: &crate::tree::Tree<D>) -> Option<RegularLeaf>
where
    crate::dim::Dim<D>: crate::dim::Dimension<D>,
{
    let s: &Solid<D> = tree.as_solid()?;
    if s.is_space_mapped() {
        return None;
    }
    let (lo, hi) = s.domain();
    Some(RegularLeaf {
        degree: s.degree().to_vec(),
        lo: <crate::dim::Dim<D> as crate::dim::Dimension<D>>::coords(lo).to_vec(),
        hi: <crate::dim::Dim<D> as crate::dim::Dimension<D>>::coords(hi).to_vec(),
        xi: s.xi_net().points().to_vec(),
    })
}

fn axis_name(axis: CoordAxis) -> &'static str {
    ["x", "y", "z"][axis.index()]
}

/// `text` with every name in `names` (HyperFun's body names, lower case: its names are not
/// case-sensitive) prefixed by `prefix`, wherever it stands as a whole name outside comments.
fn rename_bodies(text: &str, names: &[&str], prefix: &str) -> String {
    let mut out = String::with_capacity(text.len() + 64);
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        if rest.starts_with("--") {
            // A comment, to the end of its line.
            let end = rest.find('\n').unwrap_or(rest.len());
            out.push_str(&rest[..end]);
            rest = &rest[end..];
        } else if c.is_ascii_alphanumeric() || c == '_' {
            // A name or a number (whose exponent's letters are no name).
            let end = rest
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.'))
                .unwrap_or(rest.len());
            let word = &rest[..end];
            if c.is_ascii_alphabetic() && names.iter().any(|n| n.eq_ignore_ascii_case(word)) {
                out.push_str(prefix);
            }
            out.push_str(word);
            rest = &rest[end..];
        } else {
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::SolidSpec as S;
    use crate::testutil::{Rng, random_point, random_tree};
    use alloc::boxed::Box;
    use alloc::vec;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::super::interp as hf;

    fn agree(file: &ModelFile, points: &[[f64; 3]]) {
        let text = tree_hf(file).unwrap();
        let program = hf::Program::new(&text);
        let tree = file.to_tree().unwrap();
        for &p in points {
            let want = match &tree {
                ModelTree::Plane(t) => t.f(glam::DVec2::new(p[0], p[1])),
                ModelTree::Space(t) => t.f(glam::DVec3::from_array(p)),
            };
            let got = program.run(p);
            assert!(
                (got - want).abs() <= 1e-9 * want.abs().max(1.0),
                "{p:?}: HyperFun {got}, eval {want}\n{text}"
            );
        }
    }

    #[test]
    fn piecewise_solids_export_their_cells_chosen_as_eval_chooses_them() {
        let mut rng = Rng::new(8);
        for _ in 0..12 {
            let file = ModelFile::from_spec(crate::testutil::random_piecewise3(&mut rng, false));
            let points: Vec<[f64; 3]> = (0..60).map(|_| random_point(&mut rng, 1.4)).collect();
            agree(&file, &points);
        }
        // A 2D one of three by two cubic-by-linear cells, as a prism.
        let points: Vec<Vec<f64>> = (0..10)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| {
                let xi = f64::from((i * 7 + j * 3) % 5) / 4.0 - 0.4;
                vec![f64::from(i) / 3.0, f64::from(j), xi]
            })
            .collect();
        let file = ModelFile::from_spec(S::Piecewise {
            cells: vec![3, 2],
            degree: vec![3, 1],
            points,
        });
        let text = tree_hf(&file).unwrap();
        assert!(text.contains("if ("), "{text}");
        let samples: Vec<[f64; 3]> = (0..200)
            .map(|_| [rng.range(-0.5, 3.5), rng.range(-0.5, 2.5), 0.0])
            .collect();
        agree(&file, &samples);
    }

    /// A 2D model exported as a slab `0 ≤ z ≤ H`: the 2D function intersected with the slab's
    /// strip, negative below and above it; a 3D export or a bad height has no extrusion.
    #[test]
    fn two_d_models_extrude_to_a_bounded_slab() {
        let patch = crate::Solid2::fig9();
        let single = ModelFile::from_solid2(&patch);
        let tree = ModelFile::from_spec(S::Union {
            of: vec![
                single.solid.clone(),
                S::Circle {
                    center: [1.2, 0.5],
                    radius: 0.3,
                },
            ],
        });
        let mut rng = Rng::new(31);
        let and = |a: f64, b: f64| a + b - (a * a + b * b).sqrt();
        for (file, text) in [
            (&single, super::super::solid2_hf(&patch).unwrap()),
            (&tree, tree_hf(&tree).unwrap()),
        ] {
            let height = 0.5;
            let slab = super::super::extruded(&text, height).unwrap();
            assert!(slab.contains("from z = 0 to z = 0.5"), "{slab}");
            let ModelTree::Plane(t) = file.to_tree().unwrap() else {
                panic!("2D")
            };
            let mut inside = 0;
            for _ in 0..600 {
                let p = [
                    rng.range(-0.2, 1.6),
                    rng.range(-0.2, 1.2),
                    rng.range(-0.3, 0.8),
                ];
                let want = and(t.f(glam::DVec2::new(p[0], p[1])), p[2] * (height - p[2]));
                let got = hf::eval(&slab, p);
                assert!(
                    (got - want).abs() <= 1e-9 * want.abs().max(1.0),
                    "{p:?}: {got} against {want}"
                );
                if !(0.0..=height).contains(&p[2]) {
                    assert!(got < 0.0, "{p:?} is outside the slab: {got}");
                }
                inside += usize::from(got > 0.0);
            }
            assert!(inside > 10, "{inside} points inside");
        }
        let volume = super::super::solid3_hf(
            &crate::Solid3::regular([1, 1, 1], glam::DVec3::ZERO, glam::DVec3::ONE, |_| 1.0)
                .unwrap(),
        )
        .unwrap();
        assert_eq!(super::super::extruded(&volume, 1.0), None);
        let text = super::super::solid2_hf(&patch).unwrap();
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(super::super::extruded(&text, bad), None);
        }
    }

    #[test]
    fn the_export_of_random_trees_evaluates_as_eval() {
        let mut rng = Rng::new(21);
        for _ in 0..40 {
            let file = ModelFile::from_spec(random_tree(&mut rng, 3));
            let points: Vec<[f64; 3]> = (0..30).map(|_| random_point(&mut rng, 2.0)).collect();
            agree(&file, &points);
        }
    }

    #[test]
    fn the_export_of_2d_trees_and_every_kind_evaluates_as_eval() {
        let patch = ModelFile::from_solid2(&crate::Solid2::fig9()).solid;
        let file = ModelFile::from_spec(S::Transform {
            solid: Box::new(S::Difference {
                of: vec![
                    S::BlendIntersection {
                        of: vec![
                            patch,
                            S::Circle {
                                center: [0.5, 0.5],
                                radius: 0.6,
                            },
                        ],
                        a0: 0.1,
                        a1: 0.5,
                        a2: 2.0,
                    },
                    S::Rectangle {
                        min: [0.0, 0.0],
                        max: [0.3, 0.2],
                    },
                    S::Halfplane {
                        normal: [1.0, -1.0],
                        offset: 0.6,
                    },
                    S::Morph {
                        of: vec![
                            S::Circle {
                                center: [1.0, 1.0],
                                radius: 0.2,
                            },
                            S::Circle {
                                center: [0.0, 1.0],
                                radius: 0.3,
                            },
                        ],
                        t: 0.25,
                    },
                ],
            }),
            translate: Some(vec![0.25, -0.5]),
            rotate: Some(Rotation::Angle(-20.0)),
            scale: Some(vec![1.5, -0.75]),
        });
        let mut rng = Rng::new(22);
        let points: Vec<[f64; 3]> = (0..200)
            .map(|_| {
                let p = random_point(&mut rng, 1.5);
                [p[0], p[1], 0.0]
            })
            .collect();
        agree(&file, &points);
        let text = tree_hf(&file).unwrap();
        assert!(
            text.contains("hfBlendInt(") && text.contains(" \\ "),
            "{text}"
        );
    }

    /// How the export of a space-mapped solid met `eval` on a set of points.
    #[derive(Debug, Default)]
    struct Met {
        /// Points with a preimage where the values agreed to 1e-9.
        exact: usize,
        /// Points with a preimage.
        inside: usize,
        /// Points with two preimages or more.
        folded: usize,
        /// Points off the surface (`|f| > 1e-9`) where the signs differ.
        wrong_sign: usize,
    }

    /// The export `text` against `eval` (its value and preimage count) at `points`: values to 1e-9
    /// at every point with a preimage where `exact` says so, signs everywhere.
    fn meet(
        text: &str,
        points: &[[f64; 3]],
        eval: impl Fn([f64; 3]) -> (f64, usize),
        exact: bool,
    ) -> Met {
        let mut met = Met::default();
        let program = hf::Program::new(text);
        for &p in points {
            let (want, preimages) = eval(p);
            let got = program.run(p);
            let close = (got - want).abs() <= 1e-9 * want.abs().max(1.0);
            if preimages > 0 {
                met.inside += 1;
                met.exact += usize::from(close);
                assert!(!exact || close, "{p:?}: HyperFun {got}, eval {want}");
            }
            met.folded += usize::from(preimages > 1);
            if want.abs() > 1e-9 && (got > 0.0) != (want > 0.0) {
                met.wrong_sign += 1;
            }
        }
        met
    }

    fn grid2(lo: glam::DVec2, hi: glam::DVec2, n: usize) -> Vec<[f64; 3]> {
        let (lo, hi) = (lo - (hi - lo) * 0.2, hi + (hi - lo) * 0.2);
        (0..n * n)
            .map(|k| {
                let t = glam::DVec2::new((k % n) as f64, (k / n) as f64) / (n - 1) as f64;
                let p = lo + (hi - lo) * t;
                [p.x, p.y, 0.7]
            })
            .collect()
    }

    /// A space-mapped patch is written with its inverse map: where the map is certified injective
    /// the export is `eval` to 1e-9 at every point with a preimage; where it folds, every point
    /// of a dense grid has `eval`'s sign and the values agree where two preimages meet.
    #[test]
    fn space_mapped_patches_export_their_inverse_map_injective_or_folded() {
        use crate::inverse::Method;
        use glam::DVec2;
        let mut gentle = crate::Solid2::fig9();
        gentle.set_point([1, 1], DVec2::new(0.6, 0.45)).unwrap();
        gentle.set_point([2, 0], DVec2::new(1.1, -0.2)).unwrap();
        let mut folded = crate::Solid2::fig9();
        folded.set_point([1, 1], DVec2::new(3.0, 0.5)).unwrap();
        assert!(gentle.inverse().unwrap().injective());
        assert!(!folded.inverse().unwrap().injective());
        for (solid, injective) in [(&gentle, true), (&folded, false)] {
            let text = super::super::solid2_hf(solid).unwrap();
            assert!(
                text.contains("while (") && text.contains("endloop;") && text.contains("array "),
                "{text}"
            );
            let (lo, hi) = solid.domain();
            let points = grid2(lo, hi, 48);
            let met = meet(
                &text,
                &points,
                |p| {
                    let v = solid.evaluate(DVec2::new(p[0], p[1]), Method::Fast);
                    (v.f, v.preimages)
                },
                injective,
            );
            std::println!("injective {injective}: {met:?}");
            assert_eq!(met.wrong_sign, 0, "{met:?}");
            assert!(met.inside > 300, "{met:?}");
            if !injective {
                assert!(met.folded > 50, "the grid crosses the fold: {met:?}");
                assert!(met.exact * 100 >= met.inside * 99, "{met:?}");
            }
        }
    }

    /// Volumes, alone, in a tree, and a piecewise volume with moved points (each cell's
    /// preimages, clipped on the global parameter).
    #[test]
    fn space_mapped_volumes_trees_and_piecewise_solids_export_their_inverse_map() {
        use crate::inverse::Method;
        use glam::DVec3;
        let mut rng = Rng::new(43);
        let crate::model::ModelSolid::Volume(mut blob) = crate::presets::Preset::Blob.solid()
        else {
            unreachable!()
        };
        blob.set_point([1, 1, 1], DVec3::new(0.3, -0.2, 0.1))
            .unwrap();
        blob.set_point([2, 0, 2], DVec3::new(1.2, -1.1, 0.9))
            .unwrap();
        assert!(blob.inverse().unwrap().injective());
        let text = super::super::solid3_hf(&blob).unwrap();
        let points: Vec<[f64; 3]> = (0..150).map(|_| random_point(&mut rng, 1.3)).collect();
        let met = meet(
            &text,
            &points,
            |p| {
                let v = blob.evaluate(DVec3::from_array(p), Method::Fast);
                (v.f, v.preimages)
            },
            true,
        );
        assert_eq!(met.wrong_sign, 0, "{met:?}");
        assert!(met.inside > 30, "{met:?}");

        // In a tree: the union with a sphere, equal where the point has a preimage.
        let file = ModelFile::from_spec(S::Union {
            of: vec![
                S::Sphere {
                    center: [0.9, 0.9, 0.9],
                    radius: 0.5,
                },
                ModelFile::from_solid3(&blob).solid,
            ],
        });
        let text = tree_hf(&file).unwrap();
        let ModelTree::Space(tree) = file.to_tree().unwrap() else {
            unreachable!()
        };
        let met = meet(
            &text,
            &points,
            |p| {
                let v = blob.evaluate(DVec3::from_array(p), Method::Fast);
                (tree.f(DVec3::from_array(p)), v.preimages)
            },
            true,
        );
        assert_eq!(met.wrong_sign, 0, "{met:?}");

        // Piecewise volumes with moved points.
        for _ in 0..4 {
            let spec = crate::testutil::random_piecewise3(&mut rng, true);
            let file = ModelFile::from_spec(spec);
            let text = tree_hf(&file).unwrap();
            let ModelTree::Space(tree) = file.to_tree().unwrap() else {
                unreachable!()
            };
            let solid = tree.as_piecewise().unwrap();
            let points: Vec<[f64; 3]> = (0..60).map(|_| random_point(&mut rng, 1.2)).collect();
            let met = meet(
                &text,
                &points,
                |p| {
                    let v = solid.evaluate(DVec3::from_array(p), Method::Fast);
                    (v.f, v.preimages)
                },
                true,
            );
            assert_eq!(met.wrong_sign, 0, "{met:?}");
            assert!(met.inside > 5, "{met:?}");
        }
    }

    /// Past [`MAX_NUMBERS`] the export says which leaf passed it; the message names the cap.
    #[test]
    fn an_export_past_the_cap_says_so() {
        let mut fig9 = crate::Solid2::fig9();
        fig9.set_point([1, 1], glam::DVec2::new(0.6, 0.4)).unwrap();
        let leaf = ModelFile::from_solid2(&fig9).solid;
        let file = ModelFile::from_spec(S::Union {
            of: vec![leaf.clone(), leaf],
        });
        let one = mapped_leaf(&fig9).unwrap().numbers();
        let err = tree_hf_within(&file, one + 1).unwrap_err();
        assert_eq!(
            err,
            TreeHfError::TooLarge {
                path: "solid.of[1]".into(),
                numbers: 2 * one,
            }
        );
        assert!(
            alloc::string::ToString::to_string(&err).contains("more than the"),
            "{err}"
        );
        assert!(tree_hf_within(&file, 2 * one).is_ok());
    }
}
