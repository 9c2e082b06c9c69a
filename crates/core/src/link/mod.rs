//! Share links (DESIGN §5): a model in a URL fragment, `#v1.` + base64url(deflate(postcard(model))).
//!
//! The fragment never reaches a server, and a `v1` link opens forever: the wire layout below is a
//! contract, like the model file. Links are untrusted input, so [`decode`] caps the text
//! ([`MAX_LINK_CHARS`]) and the inflated data ([`MAX_INFLATED_BYTES`]), rejects trailing bytes
//! (after the deflate stream, [`LinkError::TrailingData`], and after the model in the inflated
//! data, [`LinkError::Trailing`]), and validates the model as a model file is validated; every
//! failure is a [`LinkError`].
//!
//! The postcard layout of `v1` (all integers as postcard varints, `f64` as 8 little-endian bytes):
//!
//! - variant `0`, a patch: `degree: [u8; 2]`, then three sequences of `(n + 1)(m + 1)` numbers: all
//!   `x`, all `y`, all `ξ`, each in the model file's point order;
//! - variant `1`, a volume: `degree: [u8; 3]`, then four sequences: `x`, `y`, `z`, `ξ`;
//! - variant `2`, a free-form model; variant `3`, a PLaSM script, as text;
//! - variant `4`, a tree of many solids: its nodes in prefix order, each without its children
//!   (an operation says how many follow it), patches and volumes laid out as above;
//! - variant `5`, a free-form model that variant `2` cannot say (a complement, an expression,
//!   named, rotated or scaled operands, a crease angle): each operand with its optional fields.
//! - variant `6`, a HyperFun program: its text, then its box (`None`, or `Some` of the low and
//!   the high corner, three numbers each).
//!
//! One sequence per coordinate (rather than per point) puts like numbers together, which deflate
//! turns into shorter links: the paper's Fig. 9 model gives a link of about 100 characters.
//!
//! ```
//! use bezsolid_core::{Solid2, link, model::{ModelFile, ModelSolid}};
//!
//! let solid = Solid2::fig9();
//! let fragment = link::encode(&ModelFile::from_solid2(&solid)).unwrap();
//! assert!(fragment.starts_with("#v1."));
//! let url = format!("https://example.invalid/{fragment}");
//! assert_eq!(link::decode(&url), Ok(ModelSolid::Patch(solid)));
//! assert!(link::decode("#v1.AAAA").is_err());
//! ```

use alloc::string::{String, ToString};
use alloc::vec::Vec;
use core::fmt;

use base64::Engine as _;
use base64::engine::general_purpose::URL_SAFE_NO_PAD;
use serde::{Deserialize, Serialize};

use crate::esc::bool::Op;

mod tree;
use crate::model::{EscOperand, MeshSpec, ModelError, ModelFile, ModelSolid, SolidSpec};

/// The version tag this build writes, with its separator.
pub const PREFIX: &str = "v1.";
/// The longest fragment read or written, in characters (without the `#` and the spaces around it).
/// Base64 padding never takes a link that fits past it: padded base64 is a multiple of 4
/// characters long, so the 8189 after `v1.` hold at most 8188 with their `=`.
pub const MAX_LINK_CHARS: usize = 8 * 1024;
/// How far past [`MAX_LINK_CHARS`] the text after `#` may run with spaces and line ends around
/// a link that fits: a link pasted with a line end opens, a megabyte of spaces is too long.
const LINK_SLACK: usize = 16;
/// The most bytes a link may inflate to.
pub const MAX_INFLATED_BYTES: usize = 64 * 1024;
/// The deflate level used for links (miniz's best).
const LEVEL: u8 = 10;

/// The postcard layout of a `v1` link. Variant order and field order are the contract.
#[derive(Serialize, Deserialize)]
enum Wire {
    Patch {
        degree: [u8; 2],
        x: Vec<f64>,
        y: Vec<f64>,
        xi: Vec<f64>,
    },
    Volume {
        degree: [u8; 3],
        x: Vec<f64>,
        y: Vec<f64>,
        z: Vec<f64>,
        xi: Vec<f64>,
    },
    /// A free-form model: operation 0 none, 1 union, 2 intersection, 3 difference.
    Esc {
        operation: u8,
        operands: Vec<WireOperand>,
    },
    /// A PLaSM script, as text.
    Plasm { script: String },
    /// A tree of many solids: its nodes in prefix order ([`tree`]).
    Tree { nodes: Vec<tree::Node> },
    /// A free-form model: operation as [`Wire::Esc`]'s, or 4 complement; an expression over the
    /// operands' names; operands with their optional fields.
    EscPlaced {
        operation: u8,
        expression: Option<String>,
        operands: Vec<WirePlaced>,
    },
    /// A HyperFun program, as text, and its box if the model gives one (appended).
    Hyperfun {
        program: String,
        bounds: Option<[[f64; 3]; 2]>,
    },
}

/// One operand of [`Wire::EscPlaced`]: [`WireOperand`] with its name, rotation, scale and crease
/// angle.
#[derive(Serialize, Deserialize)]
struct WirePlaced {
    name: Option<String>,
    rotate: Option<[f64; 3]>,
    scale: Option<[f64; 3]>,
    crease: Option<f64>,
    operand: WireOperand,
}

/// The operation code of [`Wire::Esc`] and [`Wire::EscPlaced`]: 0 none, 1–3 the operations of
/// [`Op::ALL`], 4 complement ([`Wire::EscPlaced`] only), 255 a name no reader knows (it fails
/// validation when read).
fn operation_code(operation: Option<&str>) -> u8 {
    match operation {
        None => 0,
        Some(crate::model::COMPLEMENT) => 4,
        Some(name) => Op::from_name(name)
            .and_then(|op| Op::ALL.iter().position(|&o| o == op))
            .map_or(u8::MAX, |i| i as u8 + 1),
    }
}

fn operation_name(code: u8) -> Option<String> {
    match code {
        0 => None,
        4 => Some(crate::model::COMPLEMENT.into()),
        k => Some(
            Op::ALL
                .get(usize::from(k) - 1)
                .map_or_else(|| "unknown".to_string(), |o| o.name().to_string()),
        ),
    }
}

fn wire_operand(o: &EscOperand) -> WireOperand {
    let example = o.example.as_deref().map_or(0, |name| {
        EXAMPLES
            .iter()
            .position(|&e| e == name)
            .map_or(u8::MAX, |i| i as u8 + 1)
    });
    let (positions, triangles) = o
        .mesh
        .as_ref()
        .map_or((&[][..], &[][..]), |m| (&m.positions[..], &m.triangles[..]));
    let [x, y, z] = columns(positions);
    WireOperand {
        example,
        offset: o.offset,
        x,
        y,
        z,
        triangles: triangles.iter().flatten().copied().collect(),
    }
}

fn operand_from_wire(o: WireOperand) -> Result<EscOperand, LinkError> {
    let example = match o.example {
        0 => None,
        k => Some(
            EXAMPLES
                .get(usize::from(k) - 1)
                .map_or_else(|| "unknown".to_string(), |e| (*e).to_string()),
        ),
    };
    let mesh = if o.example == 0 {
        if !o.triangles.len().is_multiple_of(3) {
            return Err(LinkError::Decode);
        }
        Some(MeshSpec {
            positions: rows([o.x, o.y, o.z])?,
            triangles: o
                .triangles
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
        })
    } else {
        None
    };
    Ok(EscOperand {
        example,
        mesh,
        offset: o.offset,
        ..EscOperand::default()
    })
}

/// One operand of [`Wire::Esc`]: `example` 1, 2, 3 for icosphere, torus, blob, or 0 with a mesh
/// (vertex coordinates by column, triangle indices flat).
#[derive(Serialize, Deserialize)]
struct WireOperand {
    example: u8,
    offset: [f64; 3],
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    triangles: Vec<u32>,
}

const EXAMPLES: [&str; 3] = ["icosphere", "torus", "blob"];

/// Why a link could not be made or opened.
///
/// Its message says the inner error's too (the page shows `to_string()` alone), so
/// [`source`](core::error::Error::source) gives none: a chain printed link by link (`anyhow`'s
/// `{:#}`) says each cause once, as the Rust API guidelines ask (C-GOOD-ERR: one or the other).
#[derive(Clone, Debug, PartialEq)]
pub enum LinkError {
    /// There is no fragment, or it is empty.
    Empty,
    /// The fragment is longer than [`MAX_LINK_CHARS`] (or, when encoding, the model would be).
    TooLong {
        /// Its length in characters.
        len: usize,
    },
    /// The fragment does not start with a version tag such as `v1.`.
    NotALink,
    /// A version this build does not read (the tag, e.g. `v2`).
    Version(String),
    /// The data is not base64url.
    Base64,
    /// The data has `=` where base64 padding cannot be: in the middle, more than two, or a count
    /// that does not bring the length to a multiple of 4.
    Padding,
    /// The data does not inflate: the link is damaged or cut off.
    Inflate,
    /// The data inflates past [`MAX_INFLATED_BYTES`].
    TooLarge,
    /// The inflated data is not a model in the `v1` layout.
    Decode,
    /// The inflated data goes on after the model: how many bytes.
    Trailing(usize),
    /// The packed data goes on after the end of its deflate stream: how many bytes.
    TrailingData(usize),
    /// The model is invalid (as a model file would be).
    Model(ModelError),
}

impl fmt::Display for LinkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "the link holds no model (nothing after '#')"),
            Self::TooLong { len } => write!(
                f,
                "the link's model is {len} characters long; a link holds at most {MAX_LINK_CHARS} (save a model file instead)"
            ),
            Self::NotALink => write!(
                f,
                "not a bezsolid link: the part after '#' must start with {PREFIX:?}"
            ),
            Self::Version(v) => write!(
                f,
                "the link is of version {v:?}, which this build cannot open (it reads {:?})",
                PREFIX.trim_end_matches('.')
            ),
            Self::Base64 => write!(
                f,
                "the link is damaged: it has characters that a link cannot contain"
            ),
            Self::Padding => write!(
                f,
                "the link is damaged: its '=' padding does not fit its length (a link ends in at most two '=', or none)"
            ),
            Self::Inflate => write!(f, "the link is damaged or cut off: its data is incomplete"),
            Self::TooLarge => write!(
                f,
                "the link's data unpacks to more than {MAX_INFLATED_BYTES} bytes; it is refused"
            ),
            Self::Decode => write!(f, "the link is damaged: its data is not a bezsolid model"),
            Self::Trailing(n) => write!(f, "the link is damaged: {n} stray bytes follow the model"),
            Self::TrailingData(n) => write!(
                f,
                "the link is damaged: {n} stray bytes follow the end of its packed data"
            ),
            Self::Model(e) => write!(f, "the link's model is invalid: {e}"),
        }
    }
}

impl core::error::Error for LinkError {}

impl From<ModelError> for LinkError {
    fn from(e: ModelError) -> Self {
        Self::Model(e)
    }
}

fn columns<const N: usize>(points: &[[f64; N]]) -> [Vec<f64>; N] {
    core::array::from_fn(|c| points.iter().map(|p| p[c]).collect())
}

fn rows<const N: usize>(cols: [Vec<f64>; N]) -> Result<Vec<[f64; N]>, LinkError> {
    let len = cols[0].len();
    if cols.iter().any(|c| c.len() != len) {
        return Err(LinkError::Decode);
    }
    Ok((0..len)
        .map(|k| core::array::from_fn(|c| cols[c][k]))
        .collect())
}

/// A degree as a byte; a degree past 255 becomes 0, which the reader refuses (degrees are 1 to 16).
fn byte(d: usize) -> u8 {
    u8::try_from(d).unwrap_or(0)
}

/// The fragment `#v1.…` that carries `model`.
///
/// # Errors
///
/// [`LinkError::TooLong`] when the model does not fit in [`MAX_LINK_CHARS`] (a large net of
/// arbitrary numbers: share the model file instead).
pub fn encode(model: &ModelFile) -> Result<String, LinkError> {
    let wire = match &model.solid {
        SolidSpec::Patch { degree, points } => {
            let [x, y, xi] = columns(points);
            Wire::Patch {
                degree: degree.map(byte),
                x,
                y,
                xi,
            }
        }
        SolidSpec::Volume { degree, points } => {
            let [x, y, z, xi] = columns(points);
            Wire::Volume {
                degree: degree.map(byte),
                x,
                y,
                z,
                xi,
            }
        }
        SolidSpec::Esc {
            operation,
            expression,
            operands,
        } => {
            let code = operation_code(operation.as_deref());
            let plain = expression.is_none()
                && code != 4
                && operands.iter().all(|o| {
                    o.name.is_none()
                        && o.rotate.is_none()
                        && o.scale.is_none()
                        && o.crease.is_none()
                });
            if plain {
                Wire::Esc {
                    operation: code,
                    operands: operands.iter().map(wire_operand).collect(),
                }
            } else {
                Wire::EscPlaced {
                    operation: code,
                    expression: expression.clone(),
                    operands: operands
                        .iter()
                        .map(|o| WirePlaced {
                            name: o.name.clone(),
                            rotate: o.rotate,
                            scale: o.scale,
                            crease: o.crease,
                            operand: wire_operand(o),
                        })
                        .collect(),
                }
            }
        }
        SolidSpec::Plasm { script } => Wire::Plasm {
            script: script.clone(),
        },
        SolidSpec::Hyperfun { program, bounds } => Wire::Hyperfun {
            program: program.clone(),
            bounds: *bounds,
        },
        tree => Wire::Tree {
            nodes: tree::flatten(tree)?,
        },
    };
    // Serialising into a Vec cannot fail for this type.
    let bytes = postcard::to_allocvec(&wire).map_err(|_| LinkError::Decode)?;
    let packed = miniz_oxide::deflate::compress_to_vec(&bytes, LEVEL);
    let mut out = String::with_capacity(1 + PREFIX.len() + packed.len() * 4 / 3 + 4);
    out.push('#');
    out.push_str(PREFIX);
    URL_SAFE_NO_PAD.encode_string(&packed, &mut out);
    let len = out.len() - 1;
    if len > MAX_LINK_CHARS {
        return Err(LinkError::TooLong { len });
    }
    Ok(out)
}

/// The model file carried by a link: the whole URL, the fragment with its `#`, or the fragment
/// alone. The model is not yet validated (see [`decode`]).
///
/// # Errors
///
/// Any [`LinkError`] but [`LinkError::Model`].
pub fn decode_file(link: &str) -> Result<ModelFile, LinkError> {
    let raw = match link.split_once('#') {
        Some((_, f)) => f,
        // A web address without a fragment carries no model.
        None if link.contains("://") => "",
        None => link,
    };
    // The cap holds for the text as given, before it is trimmed: a megabyte of spaces is too
    // long, not empty.
    if raw.len() > MAX_LINK_CHARS + LINK_SLACK {
        return Err(LinkError::TooLong { len: raw.len() });
    }
    let fragment = raw.trim();
    if fragment.is_empty() {
        return Err(LinkError::Empty);
    }
    if fragment.len() > MAX_LINK_CHARS {
        return Err(LinkError::TooLong {
            len: fragment.len(),
        });
    }
    let Some(data) = fragment.strip_prefix(PREFIX) else {
        // `v<digits>.` is a link of another version; anything else is not a link.
        return Err(match fragment.split_once('.') {
            Some((tag, _))
                if tag.len() > 1
                    && tag.len() <= 12
                    && tag.starts_with('v')
                    && tag[1..].bytes().all(|b| b.is_ascii_digit()) =>
            {
                LinkError::Version(tag.into())
            }
            _ => LinkError::NotALink,
        });
    };
    // Padding carries no data: a link copied through a padding base64 tool is the same link.
    let data = unpadded(data);
    if data.contains('=') {
        return Err(LinkError::Padding);
    }
    // A stray character is damage; a length or last symbol that no encoder makes is a cut.
    let packed = URL_SAFE_NO_PAD.decode(data).map_err(|e| match e {
        base64::DecodeError::InvalidByte(..) => LinkError::Base64,
        _ => LinkError::Inflate,
    })?;
    let bytes = inflate(&packed)?;
    let (wire, rest) = postcard::take_from_bytes::<Wire>(&bytes).map_err(|_| LinkError::Decode)?;
    if !rest.is_empty() {
        return Err(LinkError::Trailing(rest.len()));
    }
    let solid = match wire {
        Wire::Patch { degree, x, y, xi } => SolidSpec::Patch {
            degree: degree.map(usize::from),
            points: rows([x, y, xi])?,
        },
        Wire::Volume {
            degree,
            x,
            y,
            z,
            xi,
        } => SolidSpec::Volume {
            degree: degree.map(usize::from),
            points: rows([x, y, z, xi])?,
        },
        Wire::Esc {
            operation,
            operands,
        } => SolidSpec::Esc {
            operation: operation_name(operation),
            expression: None,
            operands: operands
                .into_iter()
                .map(operand_from_wire)
                .collect::<Result<_, _>>()?,
        },
        Wire::EscPlaced {
            operation,
            expression,
            operands,
        } => SolidSpec::Esc {
            operation: operation_name(operation),
            expression,
            operands: operands
                .into_iter()
                .map(|o| {
                    Ok(EscOperand {
                        name: o.name,
                        rotate: o.rotate,
                        scale: o.scale,
                        crease: o.crease,
                        ..operand_from_wire(o.operand)?
                    })
                })
                .collect::<Result<_, LinkError>>()?,
        },
        Wire::Plasm { script } => SolidSpec::Plasm { script },
        Wire::Hyperfun { program, bounds } => SolidSpec::Hyperfun { program, bounds },
        Wire::Tree { nodes } => tree::build(nodes)?,
    };
    Ok(ModelFile {
        format: crate::model::FORMAT.into(),
        version: crate::model::VERSION,
        solid,
    })
}

/// `data` without the base64 padding that a padding encoder appends: one or two `=` that bring
/// its length to a multiple of 4 (RFC 4648 §4). Anything else is returned whole.
fn unpadded(data: &str) -> &str {
    let bare = data.trim_end_matches('=');
    let pad = data.len() - bare.len();
    if (1..=2).contains(&pad) && (bare.len() + pad).is_multiple_of(4) {
        bare
    } else {
        data
    }
}

/// The data of one raw deflate stream that is the whole of `packed`, at most [`MAX_INFLATED_BYTES`].
///
/// miniz's `decompress` reports the input it consumed up to the end of the stream (the byte that
/// holds the final block's end code; bytes it read ahead are given back), so anything after that is
/// bytes no encoder wrote. One call into a buffer of the cap's size decides exactly as
/// `decompress_to_vec_with_limit` (which the first links were read with) does at its last size.
fn inflate(packed: &[u8]) -> Result<Vec<u8>, LinkError> {
    use miniz_oxide::inflate::TINFLStatus;
    use miniz_oxide::inflate::core::inflate_flags::TINFL_FLAG_USING_NON_WRAPPING_OUTPUT_BUF;
    use miniz_oxide::inflate::core::{DecompressorOxide, decompress};
    let mut out = alloc::vec![0; MAX_INFLATED_BYTES];
    // Kilobytes of Huffman tables: on the heap, not on a wasm stack.
    let mut state = alloc::boxed::Box::<DecompressorOxide>::default();
    let (status, consumed, written) = decompress(
        &mut state,
        packed,
        &mut out,
        0,
        TINFL_FLAG_USING_NON_WRAPPING_OUTPUT_BUF,
    );
    match status {
        TINFLStatus::Done => {}
        TINFLStatus::HasMoreOutput => return Err(LinkError::TooLarge),
        _ => return Err(LinkError::Inflate),
    }
    if let Some(extra) = packed.len().checked_sub(consumed).filter(|&n| n > 0) {
        return Err(LinkError::TrailingData(extra));
    }
    out.truncate(written);
    Ok(out)
}

/// The solid carried by a link (see [`decode_file`]), validated as a model file is.
///
/// # Errors
///
/// Any [`LinkError`].
pub fn decode(link: &str) -> Result<ModelSolid, LinkError> {
    Ok(decode_file(link)?.to_solid()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets::Preset;
    use crate::{Solid2, Solid3};
    use alloc::format;
    use alloc::string::ToString;
    use alloc::vec;
    use glam::{DVec2, DVec3};
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn file(solid: &ModelSolid) -> ModelFile {
        match solid {
            ModelSolid::Patch(s) => ModelFile::from_solid2(s),
            ModelSolid::Volume(s) => ModelFile::from_solid3(s),
        }
    }

    /// A patch with arbitrary (non-round) numbers everywhere, space-mapped.
    fn awkward_patch() -> Solid2 {
        let mut s = Solid2::fig9();
        s.set_point([1, 1], DVec2::new(0.612_345_678_901_234_5, 0.387_654_321))
            .unwrap();
        s.set_xi([0, 2], -0.123_456_789_012_345_67).unwrap();
        s.set_xi([2, 0], f64::MIN_POSITIVE).unwrap();
        s.set_xi([2, 1], -0.0).unwrap();
        s
    }

    #[test]
    fn links_round_trip_every_preset_and_mapped_nets_exactly() {
        let mut solids: Vec<ModelSolid> = Preset::ALL.iter().map(|p| p.solid()).collect();
        solids.push(ModelSolid::Patch(awkward_patch()));
        let mut s3 = Solid3::regular(
            [2, 1, 3],
            DVec3::ZERO,
            DVec3::new(1.0, 2.0, 3.0),
            |[i, j, k]| (i * 7 + j * 3 + k) as f64 / 9.0 - 0.4,
        )
        .unwrap();
        s3.set_point([1, 0, 2], DVec3::new(0.45, 0.1, 2.2)).unwrap();
        solids.push(ModelSolid::Volume(s3));
        for solid in solids {
            let f = file(&solid);
            let link = encode(&f).unwrap();
            assert!(link.starts_with("#v1."));
            assert!(
                link[1..]
                    .bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b"-_.".contains(&b)),
                "URL-safe: {link}"
            );
            // Bit-exact: the model file read back is the same, -0.0 and subnormals included.
            let back = decode_file(&link).unwrap();
            assert_eq!(back, f);
            let bits = |m: &ModelFile| format!("{:?}", m.solid).replace("-0.0", "NEG0");
            assert_eq!(bits(&back), bits(&f));
            assert_eq!(decode(&link).unwrap(), solid);
            // The whole URL and the bare fragment work too.
            assert_eq!(
                decode(&format!("http://127.0.0.1:8080/?backend=webgl2{link}")).unwrap(),
                solid
            );
            assert_eq!(decode(&link[1..]).unwrap(), solid);
        }
    }

    #[test]
    fn free_form_models_round_trip_and_stay_short() {
        use crate::esc::bool::Op;
        use crate::esc::examples::Example;
        use crate::model::{EscOperand, MeshSpec};
        let two = ModelFile::from_esc(
            Some(Op::Difference),
            vec![
                EscOperand::example(Example::Blob, [0.0; 3]),
                EscOperand::example(Example::Torus, [0.25, -0.5, 0.125]),
            ],
        );
        let link = encode(&two).unwrap();
        assert!(link.len() < 80, "{link}");
        // An operation spelled by an alias travels as the operation itself.
        let mut alias = two.clone();
        if let SolidSpec::Esc { operation, .. } = &mut alias.solid {
            *operation = Some("minus".into());
        }
        assert_eq!(decode_file(&encode(&alias).unwrap()).unwrap(), two);
        assert_eq!(decode_file(&link).unwrap(), two);
        let boolean = decode_file(&link).unwrap().to_boolean().unwrap();
        assert_eq!(boolean.solids.len(), 2);
        // A small imported mesh travels in the link; the model is the same.
        let tetra = ModelFile::from_esc(
            None,
            vec![EscOperand {
                example: None,
                mesh: Some(MeshSpec {
                    positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                    triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
                }),
                offset: [0.0; 3],
                ..EscOperand::default()
            }],
        );
        let link = encode(&tetra).unwrap();
        assert_eq!(decode_file(&link).unwrap(), tetra);
        assert!(decode_file(&link).unwrap().to_boolean().is_ok());
        // A Bézier reader refuses it with a clear reason, and the other way round.
        assert!(matches!(
            decode(&link),
            Err(LinkError::Model(ModelError::Kind(_)))
        ));
        let fig9 = ModelFile::from_solid2(&Solid2::fig9());
        assert!(matches!(fig9.to_boolean(), Err(ModelError::Kind(_))));
        // A big mesh does not fit in a link: the model file carries it.
        let ball = crate::esc::examples::icosphere(4);
        let big = ModelFile::from_esc(
            None,
            vec![EscOperand {
                example: None,
                mesh: Some(MeshSpec {
                    positions: ball.positions.iter().map(|p| p.to_array()).collect(),
                    triangles: ball.triangles.clone(),
                }),
                offset: [0.0; 3],
                ..EscOperand::default()
            }],
        );
        assert!(matches!(encode(&big), Err(LinkError::TooLong { .. })));
    }

    #[test]
    fn free_form_expressions_and_placements_round_trip() {
        use crate::esc::examples::Example;
        use crate::model::{COMPLEMENT, EscOperand};
        let placed = |example, name: Option<&str>| EscOperand {
            name: name.map(Into::into),
            rotate: Some([10.0, -20.0, 30.0]),
            scale: Some([1.5, 1.0, -0.5]),
            crease: Some(35.0),
            ..EscOperand::example(example, [0.25, 0.0, -1.0])
        };
        let many = ModelFile::from_spec(SolidSpec::Esc {
            operation: None,
            expression: Some("!(A | wing) - C & A".into()),
            operands: vec![
                EscOperand::example(Example::Blob, [0.0; 3]),
                placed(Example::Torus, Some("wing")),
                placed(Example::Icosphere, None),
            ],
        });
        let link = encode(&many).unwrap();
        assert_eq!(decode_file(&link).unwrap(), many);
        let boolean = decode_file(&link).unwrap().to_boolean().unwrap();
        assert_eq!(boolean.solids.len(), 3);
        // A complement of one operand.
        let not = ModelFile::from_spec(SolidSpec::Esc {
            operation: Some(COMPLEMENT.into()),
            expression: None,
            operands: vec![EscOperand::example(Example::Blob, [0.0; 3])],
        });
        let link = encode(&not).unwrap();
        assert_eq!(decode_file(&link).unwrap(), not);
        let boolean = decode_file(&link).unwrap().to_boolean().unwrap();
        let mut stats = crate::esc::Stats::default();
        assert_eq!(boolean.value(glam::DVec3::ZERO, &mut stats), 0);
        assert_eq!(boolean.value(glam::DVec3::splat(5.0), &mut stats), 1);
        // What the first links could say is still written as they wrote it.
        let two = ModelFile::from_esc(
            Some(Op::Union),
            vec![
                EscOperand::example(Example::Blob, [0.0; 3]),
                EscOperand::example(Example::Torus, [0.0; 3]),
            ],
        );
        let bytes = inflate(
            &URL_SAFE_NO_PAD
                .decode(&encode(&two).unwrap()[1 + PREFIX.len()..])
                .unwrap(),
        )
        .unwrap();
        assert_eq!(bytes[0], 2, "variant 2, as before expressions");
    }

    #[test]
    fn free_form_models_that_cannot_be_built_say_why() {
        use crate::model::{EscOperand, SolidSpec};
        let model = |operation: Option<&str>, operands: Vec<EscOperand>| ModelFile {
            format: crate::model::FORMAT.into(),
            version: crate::model::VERSION,
            solid: SolidSpec::Esc {
                expression: None,
                operation: operation.map(Into::into),
                operands,
            },
        };
        let ex = |name: &str| EscOperand {
            example: Some(name.into()),
            mesh: None,
            offset: [0.0; 3],
            ..EscOperand::default()
        };
        for (m, says) in [
            (
                model(Some("xor"), vec![ex("torus"), ex("blob")]),
                "unknown operation",
            ),
            (model(Some("union"), vec![ex("torus")]), "expected 2"),
            (model(None, vec![]), "expected 1"),
            (model(None, vec![ex("teapot")]), "no example"),
            (
                model(None, vec![EscOperand::default()]),
                "either an example or a mesh",
            ),
            (
                model(
                    None,
                    vec![EscOperand {
                        offset: [f64::NAN, 0.0, 0.0],
                        ..ex("torus")
                    }],
                ),
                "finite",
            ),
        ] {
            let err = m.to_boolean().unwrap_err().to_string();
            assert!(err.contains(says), "{err}");
            // Through a link too (where it survives encoding).
            if let Ok(link) = encode(&m) {
                let err = decode_file(&link)
                    .unwrap()
                    .to_boolean()
                    .unwrap_err()
                    .to_string();
                let lost = err.contains("unknown") || err.contains("no triangles");
                assert!(err.contains(says) || lost, "{err}");
            }
        }
    }

    #[test]
    fn scripts_round_trip() {
        let script = "DEF SQR = ID * ID;\nMAP:(CONS:<S1, SQR ~ S1>):(Domain:8); % é, ≤ %\n";
        let model = ModelFile::from_plasm(script);
        let link = encode(&model).expect("a link");
        let back = decode_file(&link).expect("it opens");
        assert_eq!(back, model);
        assert_eq!(back.to_script(), Ok(script));
        assert!(matches!(back.to_solid(), Err(ModelError::Kind(_))));
        assert!(matches!(back.to_boolean(), Err(ModelError::Kind(_))));
        // A long script compresses, up to the link's limits.
        let long = script.repeat(200);
        assert!(encode(&ModelFile::from_plasm(&long)).is_ok());
        let huge = ModelFile::from_plasm(&"x".repeat(crate::model::MAX_SCRIPT_BYTES + 1));
        assert!(matches!(
            huge.to_script(),
            Err(ModelError::ScriptTooLong(_))
        ));
    }

    #[test]
    fn hyperfun_programs_round_trip_with_and_without_a_box() {
        let program =
            "-- a ball, é\nmy_model(x[3], a[1]) {\n  my_model = 1 - x[1]^2 - x[2]^2 - x[3]^2;\n}\n";
        let boxed = [[-1.5, -2.0, -0.0], [1.5, 2.0, 1e-300]];
        for bounds in [None, Some(boxed)] {
            let model = ModelFile::from_hyperfun(program, bounds);
            let link = encode(&model).expect("a link");
            let back = decode_file(&link).expect("it opens");
            assert_eq!(back, model);
            // Bit for bit: -0.0 stays negative.
            assert_eq!(format!("{back:?}"), format!("{model:?}"));
            let (text, got) = back.to_hyperfun().unwrap();
            assert_eq!(text, program);
            assert_eq!(got, bounds.unwrap_or(crate::model::DEFAULT_HYPERFUN_BOX));
            // Every other reader refuses it by what it is.
            let refused = |e: ModelError| {
                let ModelError::Kind(why) = e else {
                    panic!("{e:?}")
                };
                assert!(why.contains("HyperFun program"), "{why}");
            };
            refused(back.to_solid().unwrap_err());
            refused(back.to_boolean().unwrap_err());
            assert!(matches!(back.to_script(), Err(ModelError::Kind(_))));
            let err = back.to_tree().unwrap_err().to_string();
            assert!(err.contains("HyperFun program"), "{err}");
            assert!(matches!(
                decode(&link),
                Err(LinkError::Model(ModelError::Kind(_)))
            ));
        }
        // The variant is the last of the layout, after every earlier one.
        let bytes = inflate(
            &URL_SAFE_NO_PAD
                .decode(&encode(&ModelFile::from_hyperfun("", None)).unwrap()[1 + PREFIX.len()..])
                .unwrap(),
        )
        .unwrap();
        assert_eq!(bytes, [6, 0, 0], "variant 6, no text, no box");
        // A PLaSM script is not a HyperFun program.
        assert!(matches!(
            ModelFile::from_plasm("1;").to_hyperfun(),
            Err(ModelError::Kind(_))
        ));
    }

    #[test]
    fn hyperfun_programs_with_a_bad_box_or_too_long_are_refused() {
        let program = "my_model(x[3], a[1]) { my_model = 1; }";
        for bad in [
            [[0.0; 3], [1.0, 1.0, 0.0]],
            [[0.0; 3], [1.0, -1.0, 1.0]],
            [[f64::NAN, 0.0, 0.0], [1.0; 3]],
            [[0.0; 3], [f64::INFINITY, 1.0, 1.0]],
        ] {
            let model = ModelFile::from_hyperfun(program, Some(bad));
            // It travels as it is, and is refused where it is read, in a file or a link.
            let back = decode_file(&encode(&model).unwrap()).unwrap();
            for m in [&model, &back] {
                let err = m.to_hyperfun().unwrap_err();
                assert!(
                    matches!(err, ModelError::BadBox(b) if format!("{b:?}") == format!("{bad:?}")),
                    "{err:?}"
                );
                assert!(err.to_string().contains("box"), "{err}");
            }
        }
        let long = "x".repeat(crate::hyperfun::read::MAX_SOURCE_BYTES + 1);
        let err = ModelFile::from_hyperfun(&long, None)
            .to_hyperfun()
            .unwrap_err();
        assert_eq!(
            err,
            ModelError::ProgramTooLong(crate::hyperfun::read::MAX_SOURCE_BYTES + 1)
        );
        // A box of the wrong shape is a damaged link.
        let mut bytes = postcard::to_allocvec(&Wire::Hyperfun {
            program: "m".into(),
            bounds: None,
        })
        .unwrap();
        // The box's tag as 2: neither none nor some.
        *bytes.last_mut().unwrap() = 2;
        let mut link = String::from("#v1.");
        URL_SAFE_NO_PAD.encode_string(miniz_oxide::deflate::compress_to_vec(&bytes, 6), &mut link);
        assert_eq!(decode_file(&link), Err(LinkError::Decode));
        // A box cut short.
        let mut bytes = postcard::to_allocvec(&Wire::Hyperfun {
            program: "m".into(),
            bounds: Some([[0.0; 3], [1.0; 3]]),
        })
        .unwrap();
        bytes.truncate(bytes.len() - 8);
        let mut link = String::from("#v1.");
        URL_SAFE_NO_PAD.encode_string(miniz_oxide::deflate::compress_to_vec(&bytes, 6), &mut link);
        assert_eq!(decode_file(&link), Err(LinkError::Decode));
    }

    #[test]
    fn typical_links_are_short() {
        // The issue: a typical model's link stays under 2,000 characters.
        for preset in Preset::ALL {
            let link = encode(&file(&preset.solid())).unwrap();
            assert!(link.len() < 2000, "{}: {} chars", preset.name(), link.len());
        }
        let fig9 = encode(&file(&Preset::ALL[0].solid())).unwrap();
        assert!(fig9.len() < 120, "{fig9}");
        // A 4×4 patch with every ξ and one point dragged to arbitrary numbers.
        let mut s = Solid2::regular([3, 3], DVec2::ZERO, DVec2::ONE, |[i, j]| {
            (i as f64 * 0.377 + j as f64 * 0.911).sin()
        })
        .unwrap();
        s.set_point([2, 1], DVec2::new(0.7123, 0.3345)).unwrap();
        let link = encode(&ModelFile::from_solid2(&s)).unwrap();
        assert!(link.len() < 600, "{} chars", link.len());
    }

    #[test]
    fn hostile_links_give_their_error() {
        let good = encode(&file(&Preset::ALL[0].solid())).unwrap();
        let data = &good[4..];
        let cases: Vec<(String, LinkError)> = vec![
            (String::new(), LinkError::Empty),
            ("https://x.invalid/#".into(), LinkError::Empty),
            ("https://x.invalid/?v1.AAAA".into(), LinkError::Empty),
            ("#hello".into(), LinkError::NotALink),
            ("#v.abc".into(), LinkError::NotALink),
            ("#v2.AAAA".into(), LinkError::Version("v2".into())),
            (
                format!("#v1.{}", "A".repeat(MAX_LINK_CHARS)),
                LinkError::TooLong {
                    len: MAX_LINK_CHARS + 3,
                },
            ),
            ("#v1.ab+c/".into(), LinkError::Base64),
            ("#v1.A".into(), LinkError::Inflate),
            (
                format!("#v1.{}", &data[..data.len() / 2]),
                LinkError::Inflate,
            ),
            ("#v1.".into(), LinkError::Inflate),
        ];
        for (link, expected) in cases {
            assert_eq!(decode(&link), Err(expected.clone()), "{link}");
            assert!(!expected.to_string().is_empty());
        }
    }

    #[test]
    fn links_with_base64_padding_open_as_without_it() {
        let solids = [Preset::ALL[0].solid(), ModelSolid::Patch(awkward_patch())];
        let mut pads = 0;
        for solid in &solids {
            let link = encode(&file(solid)).unwrap();
            let data = &link[4..];
            // What a padding base64 encoder writes for the same bytes.
            let padded = format!("{link}{}", "=".repeat((4 - data.len() % 4) % 4));
            pads += padded.len() - link.len();
            assert_eq!(decode(&padded).as_ref(), Ok(solid), "{padded}");
            assert_eq!(
                decode(&format!("https://x.invalid/{padded}\n")).as_ref(),
                Ok(solid)
            );
        }
        assert!(pads > 0, "no link of the test needed padding");
        // '=' where no padding encoder puts it says so, not "cut off".
        let link = encode(&file(&solids[0])).unwrap();
        let cut = 4 + (link.len() - 4) / 4 * 4;
        for bad in [
            format!("{link}==="),
            format!("{}={}", &link[..cut], &link[cut..]),
            format!("{}=", &link[..cut]),
        ] {
            let e = decode(&bad).unwrap_err();
            assert_eq!(e, LinkError::Padding, "{bad}");
            assert!(e.to_string().contains("'=' padding"), "{e}");
        }
        // Links of the longest lengths are read past the cap with their padding and a line end
        // (zeros do not inflate, but they are not too long).
        for (data, pad) in [(MAX_LINK_CHARS - 4, ""), (MAX_LINK_CHARS - 6, "==")] {
            let longest = format!("#v1.{}", "A".repeat(data));
            assert_eq!(decode_file(&longest).unwrap_err(), LinkError::Inflate);
            let padded = format!("{longest}{pad}\r\n");
            assert!(padded.len() > MAX_LINK_CHARS + 1);
            assert_eq!(decode_file(&padded).unwrap_err(), LinkError::Inflate);
        }
    }

    #[test]
    fn links_of_nothing_but_spaces_past_the_cap_are_too_long() {
        let spaces = " ".repeat(100 << 20);
        for text in [
            spaces.clone(),
            format!("#{spaces}"),
            format!("https://x.invalid/#{spaces}"),
        ] {
            let e = decode(&text).unwrap_err();
            assert!(
                matches!(e, LinkError::TooLong { len } if len == spaces.len()),
                "{e:?}"
            );
            assert!(e.to_string().contains("at most 8192"), "{e}");
        }
        // A few spaces are still no model.
        assert_eq!(decode("#   \n"), Err(LinkError::Empty));
    }

    fn pack(wire: &Wire, extra: &[u8]) -> String {
        let mut bytes = postcard::to_allocvec(wire).unwrap();
        bytes.extend_from_slice(extra);
        let mut out = String::from("#v1.");
        URL_SAFE_NO_PAD.encode_string(miniz_oxide::deflate::compress_to_vec(&bytes, 6), &mut out);
        out
    }

    #[test]
    fn well_formed_links_with_bad_models_are_refused() {
        let ok = Wire::Patch {
            degree: [1, 1],
            x: vec![0.0, 0.0, 1.0, 1.0],
            y: vec![0.0, 1.0, 0.0, 1.0],
            xi: vec![1.0; 4],
        };
        assert!(decode(&pack(&ok, &[])).is_ok());
        assert_eq!(decode(&pack(&ok, &[0, 0])), Err(LinkError::Trailing(2)));
        let bad = |wire: Wire| decode(&pack(&wire, &[]));
        assert!(matches!(
            bad(Wire::Patch {
                degree: [1, 1],
                x: vec![0.0, 0.0, 1.0, 1.0],
                y: vec![0.0, 1.0, 0.0, 1.0],
                xi: vec![f64::NAN; 4],
            }),
            Err(LinkError::Model(_))
        ));
        assert!(matches!(
            bad(Wire::Patch {
                degree: [17, 1],
                x: vec![0.0; 36],
                y: vec![0.0; 36],
                xi: vec![0.0; 36],
            }),
            Err(LinkError::Model(_))
        ));
        assert_eq!(
            bad(Wire::Patch {
                degree: [1, 1],
                x: vec![0.0; 4],
                y: vec![0.0; 3],
                xi: vec![0.0; 4],
            }),
            Err(LinkError::Decode)
        );
        // A bomb: a megabyte of zeros deflates to about a kilobyte.
        let mut out = String::from("#v1.");
        URL_SAFE_NO_PAD.encode_string(
            miniz_oxide::deflate::compress_to_vec(&vec![0u8; 1 << 20], 10),
            &mut out,
        );
        assert!(out.len() < MAX_LINK_CHARS);
        assert_eq!(decode(&out), Err(LinkError::TooLarge));
        // Random bytes that happen to inflate are still refused cleanly.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for len in 0..200 {
            let bytes: Vec<u8> = (0..len)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    state as u8
                })
                .collect();
            let mut link = String::from("#v1.");
            URL_SAFE_NO_PAD
                .encode_string(miniz_oxide::deflate::compress_to_vec(&bytes, 1), &mut link);
            assert!(decode(&link).is_err());
            let mut raw = String::from("#v1.");
            URL_SAFE_NO_PAD.encode_string(&bytes, &mut raw);
            let _ = decode(&raw);
        }
    }

    #[test]
    fn links_with_bytes_after_the_deflate_stream_are_refused() {
        let good = encode(&file(&Preset::ALL[0].solid())).unwrap();
        let packed = URL_SAFE_NO_PAD.decode(&good[4..]).unwrap();
        assert!(decode(&good).is_ok());
        for extra in [&[0u8][..], &[0, 0], &[0xff; 7], &packed[..]] {
            let mut longer = packed.clone();
            longer.extend_from_slice(extra);
            let mut link = String::from("#v1.");
            URL_SAFE_NO_PAD.encode_string(&longer, &mut link);
            assert_eq!(
                decode(&link),
                Err(LinkError::TrailingData(extra.len())),
                "{extra:?}"
            );
            assert!(
                LinkError::TrailingData(extra.len())
                    .to_string()
                    .contains("stray bytes follow the end of its packed data")
            );
        }
    }

    #[test]
    fn links_inflate_exactly_what_the_encoder_packed() {
        // Every stream miniz writes ends at its last byte: links made by any level and any data
        // (runs, noise, empty) open, so refusing trailing bytes refuses no link ever written.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for len in [0usize, 1, 2, 100, 1000, 5000, MAX_INFLATED_BYTES] {
            for runs in [false, true] {
                let data: Vec<u8> = (0..len)
                    .map(|k| {
                        state ^= state << 13;
                        state ^= state >> 7;
                        state ^= state << 17;
                        if runs { (k / 97) as u8 } else { state as u8 }
                    })
                    .collect();
                for level in [0, 1, 6, LEVEL] {
                    let packed = miniz_oxide::deflate::compress_to_vec(&data, level);
                    assert_eq!(inflate(&packed), Ok(data.clone()), "{len} {runs} {level}");
                }
            }
        }
        let one_more = vec![7u8; MAX_INFLATED_BYTES + 1];
        assert_eq!(
            inflate(&miniz_oxide::deflate::compress_to_vec(&one_more, LEVEL)),
            Err(LinkError::TooLarge)
        );
    }

    /// The message of `e` and each of its sources, as `anyhow` prints a chain with `{:#}`.
    fn chain(e: &dyn core::error::Error) -> String {
        let mut out = e.to_string();
        let mut next = e.source();
        while let Some(cause) = next {
            out.push_str(": ");
            out.push_str(&cause.to_string());
            next = cause.source();
        }
        out
    }

    #[test]
    fn link_errors_say_each_cause_once() {
        let deg17 = Wire::Patch {
            degree: [17, 1],
            x: vec![0.0; 36],
            y: vec![0.0; 36],
            xi: vec![0.0; 36],
        };
        let err = decode(&pack(&deg17, &[])).unwrap_err();
        let said = chain(&err);
        assert_eq!(
            said,
            "the link's model is invalid: invalid solid: invalid control net: degree 17 is outside 1..=16"
        );
        let mesh = ModelFile {
            format: crate::model::FORMAT.into(),
            version: crate::model::VERSION,
            solid: SolidSpec::Esc {
                expression: None,
                operation: None,
                operands: vec![EscOperand {
                    example: None,
                    mesh: Some(MeshSpec {
                        positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                        triangles: vec![[0, 1, 2]],
                    }),
                    offset: [0.0; 3],
                    ..EscOperand::default()
                }],
            },
        };
        let err = decode_file(&encode(&mesh).unwrap())
            .unwrap()
            .to_boolean()
            .unwrap_err();
        assert_eq!(
            chain(&err),
            "invalid free-form model: operand 1: the mesh is not a closed solid: 3 open edges"
        );
    }

    #[test]
    fn models_too_large_for_a_link_say_so() {
        // 17×17 points of arbitrary numbers: about 7 kB of doubles that deflate cannot shrink.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let points = (0..17 * 17)
            .map(|_| [next(), next(), next() - 0.5])
            .collect();
        let model = ModelFile {
            format: crate::model::FORMAT.into(),
            version: crate::model::VERSION,
            solid: SolidSpec::Patch {
                degree: [16, 16],
                points,
            },
        };
        match encode(&model) {
            Err(LinkError::TooLong { len }) => assert!(len > MAX_LINK_CHARS),
            other => panic!("expected TooLong, got {other:?}"),
        }
    }
}
