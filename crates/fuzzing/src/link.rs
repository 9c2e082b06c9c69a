//! The `link` target: the share-link decoder, and the round trip of whatever it opens.

use base64::Engine as _;
use bezsolid_core::link::{self, LinkError};

use crate::model::{check_model, same_file};

/// Decodes the bytes as a share link and checks what opens.
///
/// The first byte chooses how the bytes reach the decoder, so that a campaign gets past base64 and
/// deflate as well as into them:
///
/// - `0x00`: the rest is the inflated data (the postcard layout of a `v1` link); it is deflated and
///   base64-encoded here, behind `#v1.`;
/// - `0x01`: the rest is the deflated data; it is base64-encoded here, behind `#v1.`;
/// - anything else: all the bytes are the link's text (invalid UTF-8 replaced by U+FFFD), so a link
///   as a person pastes it (`#v1.…`, `v1.…` or a whole address) is a seed as it is.
///
/// # Panics
///
/// On a bug: a model that decodes but does not re-encode, or re-encodes to a link that opens to
/// another model (bit for bit) or does not open; a model that validates but does not give its own
/// file back; any panic inside the decoder or the validation (see [`crate::model()`]).
pub fn link(data: &[u8]) {
    let text = match data.split_first() {
        Some((0, payload)) => pack(&miniz_oxide_deflate(payload)),
        Some((1, deflated)) => pack(deflated),
        _ => String::from_utf8_lossy(data).into_owned(),
    };
    let Ok(file) = link::decode_file(&text) else {
        return;
    };
    match link::encode(&file) {
        Ok(again) => {
            let back = link::decode_file(&again)
                .unwrap_or_else(|e| panic!("a re-encoded link does not open ({e}): {again}"));
            assert!(
                same_file(&back, &file),
                "the re-encoded link opens to another model:\n{back:?}\nfrom\n{file:?}"
            );
        }
        // A link packed better than this build's deflate can hold more than it would write.
        Err(LinkError::TooLong { .. }) => {}
        Err(e) => panic!("a decoded model does not encode: {e}"),
    }
    let _ = check_model(&file);
}

fn pack(deflated: &[u8]) -> String {
    let mut text = String::from("#v1.");
    base64::engine::general_purpose::URL_SAFE_NO_PAD.encode_string(deflated, &mut text);
    text
}

fn miniz_oxide_deflate(bytes: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec(bytes, 6)
}
