//! What the server sends, made ready after the web build: each module under a content-hashed name
//! (cached for a year: a new build is a new name), `pkg/assets.js` naming them (the page's one
//! small indirection, revalidated on every load), and brotli and gzip copies of the modules and
//! their glue, so the server never compresses the big files while a page waits.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

/// A 64-bit FNV-1a hash of `bytes` as 16 hex digits: the content hash in file names and `ETag`s.
pub(crate) fn content_hash(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Whether a file name carries a content hash (`name.0123456789abcdef.wasm`): such a file never
/// changes, so it may be cached for good.
pub(crate) fn is_hashed(name: &str) -> bool {
    let mut parts = name.rsplit('.');
    let (_ext, hash) = (parts.next(), parts.next());
    parts.next().is_some()
        && hash.is_some_and(|h| h.len() == 16 && h.bytes().all(|b| b.is_ascii_hexdigit()))
}

/// IEEE CRC-32 (the gzip trailer's).
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// `bytes` as a gzip file (RFC 1952): a header, raw deflate, CRC-32 and length.
pub(crate) fn gzip(bytes: &[u8], level: u8) -> Vec<u8> {
    let mut out = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 0xff];
    out.extend(miniz_oxide::deflate::compress_to_vec(bytes, level));
    out.extend(crc32(bytes).to_le_bytes());
    out.extend((bytes.len() as u32).to_le_bytes());
    out
}

/// `bytes` compressed by brotli at `quality` (0 to 11).
pub(crate) fn brotli(bytes: &[u8], quality: u32) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut w = brotli::CompressorWriter::new(&mut out, 1 << 16, quality, 22);
        // Writing to a Vec cannot fail.
        let _ = w.write_all(bytes);
    }
    out
}

/// The sizes of the page's module as it travels.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Travel {
    pub(crate) brotli: u64,
    pub(crate) gzip: u64,
}

/// After wasm-bindgen (and wasm-opt) wrote `{name}_bg.wasm` and `{name}.js` into `dir`: the
/// hashed copy of the module (older hashed copies removed) and `.br` and `.gz` beside the module
/// and the glue. Returns the hashed file's name and the module's sizes as it travels.
pub(crate) fn publish(dir: &Path, name: &str) -> Result<(String, Travel)> {
    let wasm_path = dir.join(format!("{name}_bg.wasm"));
    let wasm = std::fs::read(&wasm_path).with_context(|| wasm_path.display().to_string())?;
    let hashed = format!("{name}_bg.{}.wasm", content_hash(&wasm));
    for entry in std::fs::read_dir(dir)?.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let stem = file.trim_end_matches(".br").trim_end_matches(".gz");
        if stem.starts_with(&format!("{name}_bg.")) && is_hashed(stem) && stem != hashed {
            let _ = std::fs::remove_file(entry.path());
        }
    }
    std::fs::write(dir.join(&hashed), &wasm)?;
    let mut travel = Travel { brotli: 0, gzip: 0 };
    for file in [hashed.clone(), format!("{name}.js")] {
        let path = dir.join(&file);
        let bytes = std::fs::read(&path)?;
        let br = brotli(&bytes, 11);
        let gz = gzip(&bytes, 9);
        if file == hashed {
            travel = Travel {
                brotli: br.len() as u64,
                gzip: gz.len() as u64,
            };
        }
        std::fs::write(dir.join(format!("{file}.br")), br)?;
        std::fs::write(dir.join(format!("{file}.gz")), gz)?;
    }
    Ok((hashed, travel))
}

/// `assets.js` in `dir`: each module's URL under its hashed name, `(module, hashed file)`.
pub(crate) fn write_manifest(dir: &Path, modules: &[(String, String)]) -> Result<()> {
    let mut text = String::from(
        "// Written by the xtask's web build: each module under its content-hashed name.\n\
         export const WASM = {\n",
    );
    for (module, hashed) in modules {
        text.push_str(&format!(
            "  {module}: new URL('./{hashed}', import.meta.url),\n"
        ));
    }
    text.push_str("};\n");
    std::fs::write(dir.join("assets.js"), &text)?;
    Ok(())
}

/// `offline.json` in `dir` (the modules' folder, `www/pkg`): every file the page may need, as the
/// service worker (`www/sw.js`) keeps them for opening with no network, relative to the page:
/// the page itself (`./`), the files beside it (scripts, styles, the icon and the web app
/// manifest; not the service worker, nor the pages of tests), the modules' glue and `assets.js`,
/// and each module under its hashed name.
pub(crate) fn write_offline_list(dir: &Path, modules: &[(String, String)]) -> Result<()> {
    let site = dir.parent().context("the modules' folder has a parent")?;
    let pkg = dir.file_name().and_then(|n| n.to_str()).unwrap_or("pkg");
    let mut files = vec!["./".to_string()];
    let mut beside: Vec<String> = std::fs::read_dir(site)?
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|name| {
            let ext = name.rsplit_once('.').map_or("", |(_, e)| e);
            matches!(ext, "html" | "js" | "css" | "svg" | "webmanifest") && name != "sw.js"
        })
        .collect();
    beside.sort();
    files.extend(beside);
    files.push(format!("{pkg}/assets.js"));
    for (module, hashed) in modules {
        files.push(format!("{pkg}/{module}.js"));
        files.push(format!("{pkg}/{hashed}"));
    }
    let list: Vec<String> = files.iter().map(|f| format!("    {f:?}")).collect();
    let text = format!(
        "{{\n  \"about\": \"Written by the xtask's web build: the files the service worker keeps for offline use.\",\n  \"files\": [\n{}\n  ]\n}}\n",
        list.join(",\n")
    );
    std::fs::write(dir.join("offline.json"), text)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hashed_names_are_told_apart() {
        assert!(is_hashed("bezsolid_web_bg.0123456789abcdef.wasm"));
        assert!(!is_hashed("bezsolid_web_bg.wasm"));
        assert!(!is_hashed("0123456789abcdef.wasm"));
        assert!(!is_hashed("a.0123456789abcdeg.wasm"));
        assert_eq!(content_hash(b"").len(), 16);
        assert_ne!(content_hash(b"a"), content_hash(b"b"));
    }

    #[test]
    fn gzip_and_brotli_read_back() {
        let text: Vec<u8> = (0..20_000u32)
            .flat_map(|i| (i % 251).to_le_bytes())
            .collect();
        let gz = gzip(&text, 9);
        let raw =
            miniz_oxide::inflate::decompress_to_vec(&gz[10..gz.len() - 8]).unwrap_or_default();
        assert_eq!(raw, text);
        assert_eq!(&gz[gz.len() - 8..gz.len() - 4], &crc32(&text).to_le_bytes());
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        let br = brotli(&text, 5);
        let mut back = Vec::new();
        brotli::BrotliDecompress(&mut &br[..], &mut back).unwrap_or_default();
        assert_eq!(back, text);
        assert!(br.len() < text.len() / 4);
    }
}
