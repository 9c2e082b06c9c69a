//! A small static file server for the page: loopback only, GET and HEAD, the right MIME type for
//! `.wasm`, and a Content-Security-Policy that allows what the page needs and nothing more.
//!
//! Text and the module travel compressed: brotli or gzip as the client accepts, from the copies
//! the web build wrote beside a file (`x.br`, `x.gz`, see [`crate::assets`]) or, for the small
//! files that have none, compressed as they are sent. A content-hashed name is cached for a year
//! (`immutable`); anything else is revalidated on every load by its `ETag` (a `304` when unchanged).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

/// The most a request's line and headers may take; more is answered 431.
const MAX_HEAD: u64 = 16 * 1024;

/// Scripts only from the page's origin, plus compiling WebAssembly (`'wasm-unsafe-eval'`, not
/// `'unsafe-eval'`); `fetch` of the module is `connect-src`. No inline script or style, no frames.
pub(crate) const CSP: &str = "default-src 'none'; script-src 'self' 'wasm-unsafe-eval'; \
     style-src 'self'; img-src 'self'; connect-src 'self'; manifest-src 'self'; \
     worker-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

/// Serves `root` on `listener` until the process ends, one thread per connection.
pub(crate) fn serve(listener: TcpListener, root: PathBuf) {
    accept_loop(&listener, &Arc::new(root), None);
}

/// A server on a background thread that [`Server::stop`] ends (the browser suite's).
pub(crate) struct Server {
    stop: Arc<AtomicBool>,
    addr: SocketAddr,
    thread: Option<JoinHandle<()>>,
}

impl Server {
    pub(crate) fn start(listener: TcpListener, root: PathBuf) -> std::io::Result<Self> {
        let addr = listener.local_addr()?;
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread =
            std::thread::spawn(move || accept_loop(&listener, &Arc::new(root), Some(&flag)));
        Ok(Self {
            stop,
            addr,
            thread: Some(thread),
        })
    }

    /// Stops accepting and waits for the accept loop to end.
    pub(crate) fn stop(mut self) {
        self.stop.store(true, Ordering::SeqCst);
        // Wake the blocking accept with one last connection.
        let _ = TcpStream::connect_timeout(&self.addr, Duration::from_secs(1));
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn accept_loop(listener: &TcpListener, root: &Arc<PathBuf>, stop: Option<&AtomicBool>) {
    for stream in listener.incoming() {
        if stop.is_some_and(|s| s.load(Ordering::SeqCst)) {
            return;
        }
        match stream {
            Ok(stream) => {
                let root = Arc::clone(root);
                std::thread::spawn(move || {
                    let _ = handle(stream, &root);
                });
            }
            Err(e) => {
                // Out of file descriptors and the like: say so and back off instead of spinning.
                eprintln!("serve: accept failed: {e}");
                std::thread::sleep(Duration::from_millis(100));
            }
        }
    }
}

fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()).unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "wasm" => "application/wasm",
        "json" => "application/json",
        "webmanifest" => "application/manifest+json",
        "svg" => "image/svg+xml",
        "png" => "image/png",
        "ts" => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

/// The file for a request target, or `None` for anything outside `root`.
fn resolve(root: &Path, target: &str) -> Option<PathBuf> {
    let path = target.split(['?', '#']).next().unwrap_or("/");
    let decoded = percent_decode(path)?;
    let mut out = root.to_path_buf();
    for c in Path::new(decoded.trim_start_matches('/')).components() {
        match c {
            Component::Normal(part) => out.push(part),
            Component::CurDir => {}
            _ => return None,
        }
    }
    if out.is_dir() {
        out.push("index.html");
    }
    Some(out)
}

fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = s.get(i + 1..i + 3)?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    let s = String::from_utf8(out).ok()?;
    (!s.contains('\0')).then_some(s)
}

/// What a request asked for beyond its line: the encodings it accepts and the `ETag` it holds.
#[derive(Debug, Default)]
struct Wants {
    brotli: bool,
    gzip: bool,
    etag: Option<String>,
}

impl Wants {
    fn header(&mut self, line: &str) {
        let Some((name, value)) = line.split_once(':') else {
            return;
        };
        let value = value.trim();
        if name.eq_ignore_ascii_case("accept-encoding") {
            for coding in value.split(',') {
                let mut parts = coding.split(';');
                let name = parts.next().unwrap_or("").trim();
                // `q=0` refuses a coding.
                let refused = parts.any(|p| {
                    p.trim()
                        .strip_prefix("q=")
                        .is_some_and(|q| q.trim().parse::<f64>().is_ok_and(|q| q <= 0.0))
                });
                match name {
                    "br" => self.brotli = !refused,
                    "gzip" => self.gzip = !refused,
                    _ => {}
                }
            }
        } else if name.eq_ignore_ascii_case("if-none-match") {
            self.etag = Some(value.to_owned());
        }
    }
}

/// Whether a file of this type is worth compressing (text and WebAssembly; images are already).
fn compressible(path: &Path) -> bool {
    matches!(
        path.extension().and_then(|e| e.to_str()),
        Some("html" | "js" | "mjs" | "css" | "wasm" | "json" | "svg" | "ts" | "webmanifest")
    )
}

/// The body to send for `path` (whose bytes are `raw`) and its `Content-Encoding`: a precompressed
/// copy newer than the file, or the file compressed now (small files only), or the file itself.
fn encoded(path: &Path, raw: Vec<u8>, wants: &Wants) -> (Vec<u8>, Option<&'static str>) {
    if !compressible(path) {
        return (raw, None);
    }
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    let copy = |ext: &str| {
        let mut name = path.as_os_str().to_owned();
        name.push(ext);
        let copy = PathBuf::from(name);
        match (modified(path), modified(&copy)) {
            (Some(file), Some(c)) if c >= file => std::fs::read(&copy).ok(),
            _ => None,
        }
    };
    /// Files above this are sent as they are when no compressed copy was made for them.
    const COMPRESS_NOW: usize = 512 * 1024;
    if wants.brotli {
        if let Some(body) = copy(".br") {
            return (body, Some("br"));
        }
        if raw.len() <= COMPRESS_NOW {
            return (crate::assets::brotli(&raw, 5), Some("br"));
        }
    }
    if wants.gzip {
        if let Some(body) = copy(".gz") {
            return (body, Some("gzip"));
        }
        if raw.len() <= COMPRESS_NOW {
            return (crate::assets::gzip(&raw, 6), Some("gzip"));
        }
    }
    (raw, None)
}

fn handle(stream: TcpStream, root: &Path) -> std::io::Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(10)))?;
    stream.set_write_timeout(Some(Duration::from_secs(10)))?;
    let mut reader = BufReader::new(stream.try_clone()?.take(MAX_HEAD));
    let mut request = String::new();
    reader.read_line(&mut request)?;
    let mut wants = Wants::default();
    let mut complete = false;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line)? == 0 {
            break;
        }
        if line == "\r\n" || line == "\n" {
            complete = true;
            break;
        }
        wants.header(&line);
    }
    let mut stream = stream;
    if !complete {
        return respond(
            &mut stream,
            "431 Request Header Fields Too Large",
            "text/plain",
            b"bad request\n",
            true,
        );
    }
    let mut parts = request.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or("/"));
    if method != "GET" && method != "HEAD" {
        return respond(
            &mut stream,
            "405 Method Not Allowed",
            "text/plain",
            b"method not allowed\n",
            true,
        );
    }
    let file = resolve(root, target).and_then(|p| std::fs::read(&p).ok().map(|b| (p, b)));
    let with_body = method == "GET";
    let Some((path, raw)) = file else {
        return respond(
            &mut stream,
            "404 Not Found",
            "text/plain",
            b"not found\n",
            with_body,
        );
    };
    let hashed = path
        .file_name()
        .and_then(|n| n.to_str())
        .is_some_and(crate::assets::is_hashed);
    let etag = format!("\"{}\"", crate::assets::content_hash(&raw));
    let cache = if hashed {
        "public, max-age=31536000, immutable"
    } else {
        "no-cache"
    };
    let mut extra = format!("Cache-Control: {cache}\r\nETag: {etag}\r\n");
    if compressible(&path) {
        extra.push_str("Vary: Accept-Encoding\r\n");
    }
    if wants.etag.as_deref() == Some(etag.as_str()) {
        return send(&mut stream, "304 Not Modified", None, &extra, &[], false);
    }
    let (body, encoding) = encoded(&path, raw, &wants);
    if let Some(coding) = encoding {
        extra.push_str(&format!("Content-Encoding: {coding}\r\n"));
    }
    send(
        &mut stream,
        "200 OK",
        Some(content_type(&path)),
        &extra,
        &body,
        with_body,
    )
}

fn respond(
    stream: &mut TcpStream,
    status: &str,
    kind: &str,
    body: &[u8],
    with_body: bool,
) -> std::io::Result<()> {
    send(
        stream,
        status,
        Some(kind),
        "Cache-Control: no-cache\r\n",
        body,
        with_body,
    )
}

/// The response: `extra` is more header lines, each ending in CRLF.
fn send(
    stream: &mut TcpStream,
    status: &str,
    kind: Option<&str>,
    extra: &str,
    body: &[u8],
    with_body: bool,
) -> std::io::Result<()> {
    let kind = kind.map_or(String::new(), |k| format!("Content-Type: {k}\r\n"));
    let head = format!(
        "HTTP/1.1 {status}\r\n{kind}Content-Length: {}\r\n\
         Content-Security-Policy: {CSP}\r\nX-Content-Type-Options: nosniff\r\n\
         {extra}Connection: close\r\n\r\n",
        body.len()
    );
    stream.write_all(head.as_bytes())?;
    if with_body {
        stream.write_all(body)?;
    }
    stream.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolve_stays_inside_root() {
        let root = Path::new("/srv/www");
        assert_eq!(
            resolve(root, "/pkg/a.js?x=1"),
            Some(PathBuf::from("/srv/www/pkg/a.js"))
        );
        assert_eq!(resolve(root, "/../etc/passwd"), None);
        assert_eq!(resolve(root, "/%2e%2e/etc/passwd"), None);
        assert_eq!(resolve(root, "/a%00b"), None);
        assert_eq!(resolve(root, "/a%zz"), None);
    }

    #[test]
    fn accepted_encodings_are_read() {
        let mut w = Wants::default();
        w.header("Accept-Encoding: gzip, deflate, br;q=0\r\n");
        assert!(w.gzip && !w.brotli);
        let mut w = Wants::default();
        w.header("accept-encoding: br, gzip;q=0.5\r\n");
        w.header("If-None-Match: \"abc\"\r\n");
        assert!(w.gzip && w.brotli);
        assert_eq!(w.etag.as_deref(), Some("\"abc\""));
    }

    #[test]
    fn wasm_gets_its_mime_type() {
        assert_eq!(content_type(Path::new("x_bg.wasm")), "application/wasm");
    }
}
