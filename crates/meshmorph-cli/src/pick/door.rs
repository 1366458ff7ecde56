//! The door of `meshmorph pick`: a small HTTP/1.1 server on the loopback
//! address only, for one page.
//!
//! - It listens on `127.0.0.1` (and `::1` on the same port where the
//!   system has it), never on another address.
//! - Every request names the token (random, 128 bits, new for each run) as
//!   the first segment of its path: `/TOKEN/...`. The page's own relative
//!   URLs (its scripts, three.js's imports, its API calls) carry it without
//!   further work; a request without it or with another is refused (403).
//! - A request whose `Host` is not the loopback address with this port, or
//!   whose `Origin` (when sent) is not the page's own, is refused (403):
//!   another site, even one whose name resolves to 127.0.0.1 (DNS
//!   rebinding), cannot read or write through the door.
//! - Requests are bounded: the request line and headers to
//!   [`MAX_HEAD`], a body to [`MAX_BODY`] (413 past it, announced by
//!   `Content-Length`; chunked bodies are refused with 411), a slow client to
//!   [`IDLE`] per read, and [`MAX_CONNECTIONS`] at once (503 past them).
//! - Anything malformed gets a 4xx with a one-line reason; the server goes
//!   on. Every response closes its connection.
//!
//! What a request may do is the caller's [`Handler`]; the door hands it only
//! requests that passed every check, with the token stripped from the path.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, Ipv6Addr, SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

/// The largest request line and headers, together.
pub const MAX_HEAD: usize = 16 * 1024;
/// The largest request body (a marker list of [`super::session::MAX_MARKERS`]
/// pairs fits with room to spare).
pub const MAX_BODY: usize = 4 * 1024 * 1024;
/// The longest wait for a client's next bytes.
pub const IDLE: Duration = Duration::from_secs(10);
/// The most connections served at once.
pub const MAX_CONNECTIONS: usize = 32;

/// A request that passed the door.
#[derive(Debug)]
pub struct Request {
    pub method: String,
    /// The path after `/TOKEN`, starting with `/` (`/` for the page), without
    /// the query.
    pub path: String,
    pub body: Vec<u8>,
}

/// A response: status, content type and body.
#[derive(Debug)]
pub struct Response {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
    /// The session ends once this response is sent ([`Handler::ended`]).
    pub last: bool,
    /// Where a redirection points.
    pub location: Option<String>,
}

impl Response {
    fn new(status: u16, content_type: &'static str, body: Vec<u8>) -> Self {
        Self {
            status,
            content_type,
            body,
            last: false,
            location: None,
        }
    }

    pub fn ok(content_type: &'static str, body: Vec<u8>) -> Self {
        Self::new(200, content_type, body)
    }

    pub fn json(value: &serde_json::Value) -> Self {
        Self::ok("application/json", value.to_string().into_bytes())
    }

    /// A refusal or failure with its reason as JSON (`{"error": ...}`).
    pub fn error(status: u16, message: &str) -> Self {
        let body = serde_json::json!({ "error": message }).to_string();
        Self::new(status, "application/json", body.into_bytes())
    }
}

/// What the door hands requests to.
pub trait Handler: Send + Sync + 'static {
    fn handle(&self, request: Request) -> Response;
    /// Called once a response marked [`Response::last`] has been sent.
    fn ended(&self);
}

/// The listening door: its address and token.
pub struct Door {
    listeners: Vec<TcpListener>,
    port: u16,
    token: String,
}

impl Door {
    /// Listens on `127.0.0.1:port` (0: a free port) and on `::1` with the
    /// same port where the system has IPv6 loopback.
    ///
    /// # Errors
    /// If `127.0.0.1` cannot be bound (the port taken), or the system has no
    /// randomness for the token.
    pub fn open(port: u16) -> Result<Self> {
        let v4 = TcpListener::bind(SocketAddr::from((Ipv4Addr::LOCALHOST, port)))
            .with_context(|| format!("listening on 127.0.0.1 port {port}"))?;
        let port = v4.local_addr()?.port();
        let mut listeners = vec![v4];
        if let Ok(v6) = TcpListener::bind(SocketAddr::from((Ipv6Addr::LOCALHOST, port))) {
            listeners.push(v6);
        }
        let mut bytes = [0u8; 16];
        getrandom::fill(&mut bytes)
            .map_err(|e| anyhow::anyhow!("no randomness for the token: {e}"))?;
        let token = bytes.iter().map(|b| format!("{b:02x}")).collect();
        Ok(Self {
            listeners,
            port,
            token,
        })
    }

    /// The page's address, token included.
    pub fn url(&self) -> String {
        format!("http://127.0.0.1:{}/{}/", self.port, self.token)
    }

    /// Serves `handler` on every listener, each connection on a thread of
    /// its own; returns at once (the listeners run until the process ends).
    pub fn serve(self, handler: Arc<dyn Handler>) {
        let checks = Arc::new(Checks {
            port: self.port,
            token: self.token,
        });
        let open = Arc::new(AtomicUsize::new(0));
        for listener in self.listeners {
            let (checks, handler, open) = (checks.clone(), handler.clone(), open.clone());
            let spawned = std::thread::Builder::new()
                .name("pick-door".into())
                .spawn(move || accept(listener, checks, handler, open));
            if let Err(e) = spawned {
                eprintln!("warning: cannot listen on one address: {e}");
            }
        }
    }
}

/// One of the [`MAX_CONNECTIONS`] connections served at once, given back
/// when dropped (also when a handler panics).
struct Slot(Arc<AtomicUsize>);

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// What every request is checked against.
struct Checks {
    port: u16,
    token: String,
}

fn accept(
    listener: TcpListener,
    checks: Arc<Checks>,
    handler: Arc<dyn Handler>,
    open: Arc<AtomicUsize>,
) {
    for stream in listener.incoming() {
        let Ok(mut stream) = stream else { continue };
        if open.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            open.fetch_sub(1, Ordering::SeqCst);
            let _ = respond(&mut stream, &Response::error(503, "too many connections"));
            continue;
        }
        let slot = Slot(open.clone());
        let (checks, handler) = (checks.clone(), handler.clone());
        // A thread that cannot start drops its slot with the closure.
        let _ = std::thread::Builder::new()
            .name("pick-request".into())
            .spawn(move || {
                let _slot = slot;
                let _ = stream.set_write_timeout(Some(IDLE));
                let response = match read_request(&mut stream, &checks) {
                    Ok(request) => std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                        handler.handle(request)
                    }))
                    .unwrap_or_else(|_| {
                        Response::error(500, "the request failed inside meshmorph")
                    }),
                    Err(refusal) => refusal,
                };
                let _ = respond(&mut stream, &response);
                if response.last {
                    handler.ended();
                }
            });
    }
}

/// Reads one request and checks it; a refusal is the response to send.
/// The whole request must arrive within [`IDLE`]; the token is checked as
/// soon as the request line has.
fn read_request(stream: &mut TcpStream, checks: &Checks) -> std::result::Result<Request, Response> {
    let bad = |m: &str| Response::error(400, m);
    let deadline = Instant::now() + IDLE;
    let in_time = |s: &TcpStream| -> std::result::Result<(), Response> {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(Response::error(408, "the request was not sent in time"));
        }
        s.set_read_timeout(Some(left))
            .map_err(|_| Response::error(500, "cannot wait for the request"))
    };
    let mut reader = BufReader::new(stream.take(MAX_HEAD as u64));
    let mut lines: Vec<String> = Vec::new();
    let mut rest = None;
    loop {
        in_time(reader.get_ref().get_ref())?;
        let mut line = Vec::new();
        match reader.read_until(b'\n', &mut line) {
            Ok(0) => return Err(bad("the request ended before its headers did")),
            Ok(_) if !line.ends_with(b"\n") => {
                return Err(Response::error(431, "the request's headers are too long"))
            }
            Ok(_) => {}
            Err(_) => return Err(Response::error(408, "the request was not sent in time")),
        }
        let text = String::from_utf8(line).map_err(|_| bad("the headers are not UTF-8"))?;
        let text = text.trim_end_matches(['\r', '\n']).to_string();
        if text.is_empty() {
            break;
        }
        if lines.is_empty() {
            rest = Some(request_line(&text, checks)?);
        } else if text.starts_with([' ', '\t']) {
            return Err(bad("folded header lines are not taken"));
        }
        lines.push(text);
    }
    let (method, rest) = rest.ok_or_else(|| bad("no request line"))?;
    let mut host = None;
    let mut origin = None;
    let mut length = None;
    for line in &lines[1..] {
        let (name, value) = line
            .split_once(':')
            .ok_or_else(|| bad("malformed header"))?;
        if name.is_empty() || name.contains(|c: char| c.is_whitespace()) {
            return Err(bad("malformed header name"));
        }
        let value = value.trim();
        match name.to_ascii_lowercase().as_str() {
            "host" if host.is_some() => return Err(bad("two Host headers")),
            "host" => host = Some(value.to_string()),
            "origin" if origin.is_some() => return Err(bad("two Origin headers")),
            "origin" => origin = Some(value.to_string()),
            "content-length" if length.is_some() => return Err(bad("two Content-Length headers")),
            "content-length" => {
                if value.is_empty() || !value.bytes().all(|b| b.is_ascii_digit()) {
                    return Err(bad("bad Content-Length"));
                }
                length = Some(value.parse::<usize>().unwrap_or(usize::MAX));
            }
            "transfer-encoding" => {
                return Err(Response::error(411, "send the body with a Content-Length"))
            }
            _ => {}
        }
    }
    let allowed = |h: &str| {
        let port = checks.port;
        [
            format!("127.0.0.1:{port}"),
            format!("localhost:{port}"),
            format!("[::1]:{port}"),
        ]
        .iter()
        .any(|a| a.eq_ignore_ascii_case(h))
    };
    if !host.as_deref().is_some_and(allowed) {
        return Err(Response::error(403, "the Host is not this loopback server"));
    }
    if let Some(origin) = &origin {
        let ours = origin.strip_prefix("http://").is_some_and(allowed);
        if !ours {
            return Err(Response::error(403, "the Origin is not this page"));
        }
    }
    let Some(rest) = rest else {
        // The page's address without its last slash: its relative URLs
        // would lose the token.
        let mut moved = Response::error(308, "the page is at /TOKEN/");
        moved.location = Some(format!("/{}/", checks.token));
        return Err(moved);
    };
    let length = length.unwrap_or(0);
    if length > MAX_BODY {
        return Err(Response::error(413, "the body is too large"));
    }
    // The headers' reader may hold the first bytes of the body.
    let mut body = Vec::with_capacity(length);
    let buffered = reader.buffer().len().min(length);
    body.extend_from_slice(&reader.buffer()[..buffered]);
    let stream = reader.into_inner().into_inner();
    let mut left = length - buffered;
    let mut chunk = [0u8; 64 * 1024];
    while left > 0 {
        in_time(stream)?;
        let n = stream
            .read(&mut chunk[..left.min(64 * 1024)])
            .map_err(|_| Response::error(408, "the body was not sent in time"))?;
        if n == 0 {
            return Err(bad("the body is shorter than its Content-Length"));
        }
        body.extend_from_slice(&chunk[..n]);
        left -= n;
    }
    Ok(Request {
        method,
        path: rest,
        body,
    })
}

/// The method and the path after the token (None for `/TOKEN` without its
/// slash) of a request line, the token checked.
fn request_line(
    line: &str,
    checks: &Checks,
) -> std::result::Result<(String, Option<String>), Response> {
    let mut parts = line.split(' ');
    let (Some(method), Some(target), Some(version), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(Response::error(400, "malformed request line"));
    };
    if !version.starts_with("HTTP/1.") {
        return Err(Response::error(505, "only HTTP/1.x is spoken here"));
    }
    let path = target.split(['?', '#']).next().unwrap_or_default();
    let p = path
        .strip_prefix('/')
        .ok_or_else(|| Response::error(403, "no or wrong token"))?;
    let (token, rest) = match p.split_once('/') {
        Some((token, rest)) => (token, Some(format!("/{rest}"))),
        None => (p, None),
    };
    if !same(token.as_bytes(), checks.token.as_bytes()) {
        return Err(Response::error(403, "no or wrong token"));
    }
    Ok((method.to_string(), rest))
}

/// Compares two tokens in time that does not depend on where they differ.
fn same(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

fn respond(stream: &mut TcpStream, r: &Response) -> std::io::Result<()> {
    let reason = match r.status {
        200 => "OK",
        308 => "Permanent Redirect",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        411 => "Length Required",
        413 => "Content Too Large",
        422 => "Unprocessable Content",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        503 => "Service Unavailable",
        505 => "HTTP Version Not Supported",
        _ => "",
    };
    let location = r
        .location
        .as_ref()
        .map(|l| format!("Location: {l}\r\n"))
        .unwrap_or_default();
    let head = format!(
        "HTTP/1.1 {} {reason}\r\n{location}Content-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nReferrer-Policy: no-referrer\r\nContent-Security-Policy: default-src 'self'; img-src 'self' data: blob:; connect-src 'self'; frame-ancestors 'none'\r\nConnection: close\r\n\r\n",
        r.status,
        r.content_type,
        r.body.len()
    );
    stream.write_all(head.as_bytes())?;
    stream.write_all(&r.body)?;
    stream.flush()?;
    let _ = stream.shutdown(std::net::Shutdown::Write);
    // What the client sent beyond what was read (a refused body) is read
    // away, a little and briefly, so that closing does not reset the
    // connection before the client has read the response.
    let _ = stream.set_read_timeout(Some(Duration::from_millis(200)));
    let mut sink = [0u8; 16 * 1024];
    for _ in 0..64 {
        match stream.read(&mut sink) {
            Ok(n) if n > 0 => {}
            _ => break,
        }
    }
    Ok(())
}
