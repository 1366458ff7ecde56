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
//!   `Content-Length`; chunked bodies are refused with 411).
//! - Every connection has a total deadline, however its bytes trickle in:
//!   [`Limits::head`] from its acceptance to the end of its headers, then
//!   [`Limits::body`] for its body (408 past either).
//! - Connections that have not yet shown the token cannot starve one that
//!   has: they wait apart, at most [`Limits::pending`] of them (past that
//!   the longest waiting is closed to make room), while connections whose
//!   request line carries the token are served, [`Limits::served`] at
//!   once (503 past them). So a flood of silent or trickling connections
//!   delays nobody who has the page's address.
//! - Anything malformed gets a 4xx with a one-line reason; the server goes
//!   on. Every response closes its connection.
//!
//! What a request may do is the caller's [`Handler`]; the door hands it only
//! requests that passed every check, with the token stripped from the path.

use std::collections::VecDeque;
use std::io::{Read, Write};
use std::net::{Ipv4Addr, Ipv6Addr, Shutdown, SocketAddr, TcpListener, TcpStream};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

/// The largest request line and headers, together.
pub const MAX_HEAD: usize = 16 * 1024;
/// The largest request body (a marker list of [`super::session::MAX_MARKERS`]
/// pairs fits with room to spare).
pub const MAX_BODY: usize = 4 * 1024 * 1024;

/// The door's deadlines and caps.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// From a connection's acceptance to the end of its headers: 10 s.
    pub head: Duration,
    /// From the end of the headers to the end of the body: 30 s (a body
    /// of [`MAX_BODY`] takes milliseconds on the loopback).
    pub body: Duration,
    /// Connections held at once that have not yet shown the token: 256
    /// (past them, the one waiting longest is closed).
    pub pending: usize,
    /// Connections served at once that have shown it: 32 (503 past them).
    pub served: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            head: Duration::from_secs(10),
            body: Duration::from_secs(30),
            pending: 256,
            served: 32,
        }
    }
}

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

/// The listening door: its address, token and limits.
pub struct Door {
    listeners: Vec<TcpListener>,
    port: u16,
    token: String,
    limits: Limits,
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
            limits: Limits::default(),
        })
    }

    /// The same door with other deadlines and caps.
    #[cfg(test)]
    fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }

    /// The page's address, token included.
    pub fn url(&self) -> String {
        format!("http://127.0.0.1:{}/{}/", self.port, self.token)
    }

    /// Serves `handler` on every listener, each connection on a thread of
    /// its own; returns at once (the listeners run until the process
    /// ends), with what [`Served::settle`] waits on.
    pub fn serve(self, handler: Arc<dyn Handler>) -> Served {
        let shared = Arc::new(Shared {
            checks: Checks {
                port: self.port,
                token: self.token,
            },
            limits: self.limits,
            pending: Arc::new(Pending::default()),
            served: Arc::new(Count::default()),
            handler,
        });
        for listener in self.listeners {
            let shared = shared.clone();
            let spawned = std::thread::Builder::new()
                .name("pick-door".into())
                .spawn(move || accept(listener, shared));
            if let Err(e) = spawned {
                tell!("warning: cannot listen on one address: {e}");
            }
        }
        Served {
            count: shared.served.clone(),
            pending: shared.pending.clone(),
            longest: self.limits.head + self.limits.body,
        }
    }
}

/// How long the end of a session waits for connections that arrived but
/// have not yet shown the token (they are answered too, if they do).
const GRACE: Duration = Duration::from_secs(1);

/// The connections being read or answered, for the end of a session.
pub struct Served {
    count: Arc<Count>,
    pending: Arc<Pending>,
    longest: Duration,
}

impl Served {
    /// Waits until every request that has shown the token has been
    /// answered (a save whose body was still arriving when "done" was
    /// answered is answered too: refused, the session having ended), at
    /// most a request's two deadlines, and, for at most [`GRACE`], until the
    /// connections already accepted have shown theirs or gone.
    pub fn settle(&self) {
        let begin = Instant::now();
        loop {
            let served = *self.count.n.lock().unwrap_or_else(|e| e.into_inner());
            let waited = begin.elapsed();
            if (served == 0 && (self.pending.is_empty() || waited >= GRACE))
                || waited >= self.longest
            {
                return;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}

/// What every connection's thread shares.
struct Shared {
    checks: Checks,
    limits: Limits,
    pending: Arc<Pending>,
    served: Arc<Count>,
    handler: Arc<dyn Handler>,
}

/// What every request is checked against.
struct Checks {
    port: u16,
    token: String,
}

/// A count of connections.
#[derive(Default)]
struct Count {
    n: Mutex<usize>,
}

/// One of the served connections, given back when dropped (also when a
/// handler panics).
struct Slot(Arc<Count>);

impl Count {
    /// A slot, unless `cap` are taken.
    fn take(self: &Arc<Self>, cap: usize) -> Option<Slot> {
        let mut n = self.n.lock().unwrap_or_else(|e| e.into_inner());
        (*n < cap).then(|| {
            *n += 1;
            Slot(self.clone())
        })
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        *self.0.n.lock().unwrap_or_else(|e| e.into_inner()) -= 1;
    }
}

/// The connections that have not yet shown the token, oldest first, each
/// with a handle to close it by.
#[derive(Default)]
struct Pending {
    list: Mutex<(u64, VecDeque<(u64, TcpStream)>)>,
}

/// A connection's place among the pending ones, left when dropped.
struct Ticket {
    id: u64,
    pending: Arc<Pending>,
}

impl Pending {
    fn is_empty(&self) -> bool {
        let list = self.list.lock().unwrap_or_else(|e| e.into_inner());
        list.1.is_empty()
    }

    /// Adds `stream` (closing the oldest pending connection when `cap` are
    /// held); `None` when it cannot be held at all.
    fn admit(self: &Arc<Self>, stream: &TcpStream, cap: usize) -> Option<Ticket> {
        let handle = stream.try_clone().ok()?;
        let mut list = self.list.lock().unwrap_or_else(|e| e.into_inner());
        while list.1.len() >= cap.max(1) {
            if let Some((_, oldest)) = list.1.pop_front() {
                let _ = oldest.shutdown(Shutdown::Both);
            }
        }
        list.0 += 1;
        let id = list.0;
        list.1.push_back((id, handle));
        Some(Ticket {
            id,
            pending: self.clone(),
        })
    }
}

impl Drop for Ticket {
    fn drop(&mut self) {
        let mut list = self.pending.list.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(k) = list.1.iter().position(|(id, _)| *id == self.id) {
            list.1.remove(k);
        }
    }
}

fn accept(listener: TcpListener, shared: Arc<Shared>) {
    for stream in listener.incoming() {
        let Ok(stream) = stream else {
            // Out of file descriptors, say: a moment for others to close.
            std::thread::sleep(Duration::from_millis(10));
            continue;
        };
        let accepted = Instant::now();
        // Admitted here, in the order connections arrive.
        let Some(ticket) = shared.pending.admit(&stream, shared.limits.pending) else {
            continue;
        };
        let shared = shared.clone();
        // A thread that cannot start drops the connection with the closure.
        let _ = std::thread::Builder::new()
            .name("pick-request".into())
            .spawn(move || serve_one(stream, accepted, ticket, &shared));
    }
}

/// Reads, checks and answers one connection's request.
fn serve_one(mut stream: TcpStream, accepted: Instant, ticket: Ticket, shared: &Shared) {
    let _ = stream.set_write_timeout(Some(shared.limits.head));
    let mut ticket = Some(ticket);
    let mut slot = None;
    // The token shown: no longer pending, served if a slot is free.
    let mut shown = || {
        ticket = None;
        slot = shared.served.take(shared.limits.served);
        match slot {
            Some(_) => Ok(()),
            None => Err(Response::error(503, "too many connections")),
        }
    };
    let read = read_request(&mut stream, shared, accepted, &mut shown);
    let response = match read {
        Ok(request) => std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            shared.handler.handle(request)
        }))
        .unwrap_or_else(|_| Response::error(500, "the request failed inside meshmorph")),
        Err(refusal) => refusal,
    };
    let _ = respond(&mut stream, &response);
    if response.last {
        shared.handler.ended();
    }
    drop(slot);
}

/// Reads up to `buf.len()` bytes before `deadline`; `late` says what was
/// not sent in time.
fn read_by(
    stream: &mut TcpStream,
    deadline: Instant,
    buf: &mut [u8],
    late: &str,
) -> std::result::Result<usize, Response> {
    let left = deadline.saturating_duration_since(Instant::now());
    if left.is_zero() {
        return Err(Response::error(408, late));
    }
    stream
        .set_read_timeout(Some(left))
        .map_err(|_| Response::error(500, "cannot wait for the request"))?;
    stream.read(buf).map_err(|_| Response::error(408, late))
}

/// Where the headers end in `head` (just past the empty line), looking
/// from `from` on.
fn head_end(head: &[u8], from: usize) -> Option<usize> {
    let from = from.min(head.len());
    head[from..]
        .windows(2)
        .position(|w| w == b"\n\n")
        .map(|k| from + k + 2)
        .into_iter()
        .chain(
            head[from..]
                .windows(3)
                .position(|w| w == b"\n\r\n")
                .map(|k| from + k + 3),
        )
        .min()
}

/// Reads one request and checks it; a refusal is the response to send.
/// The request line and headers must arrive within [`Limits::head`] of
/// the connection's acceptance, the body within [`Limits::body`] after
/// them; `shown` is called once the request line has shown the token.
fn read_request(
    stream: &mut TcpStream,
    shared: &Shared,
    accepted: Instant,
    shown: &mut dyn FnMut() -> std::result::Result<(), Response>,
) -> std::result::Result<Request, Response> {
    let checks = &shared.checks;
    let bad = |m: &str| Response::error(400, m);
    let late = "the request was not sent in time";
    let deadline = accepted + shared.limits.head;
    let mut head: Vec<u8> = Vec::with_capacity(2048);
    let mut buf = [0u8; 8192];
    let mut first = None;
    let end = loop {
        let n = read_by(stream, deadline, &mut buf, late)?;
        if n == 0 {
            return Err(bad("the request ended before its headers did"));
        }
        let from = head.len().saturating_sub(2);
        head.extend_from_slice(&buf[..n]);
        if first.is_none() {
            if let Some(eol) = head.iter().position(|&b| b == b'\n') {
                let line = std::str::from_utf8(&head[..eol])
                    .map_err(|_| bad("the headers are not UTF-8"))?;
                first = Some(request_line(line.trim_end_matches('\r'), checks)?);
                shown()?;
            }
        }
        if let Some(end) = head_end(&head, from) {
            break end;
        }
        if head.len() > MAX_HEAD {
            return Err(Response::error(431, "the request's headers are too long"));
        }
    };
    if end > MAX_HEAD {
        return Err(Response::error(431, "the request's headers are too long"));
    }
    let (method, rest) = first.ok_or_else(|| bad("no request line"))?;
    let text = std::str::from_utf8(&head[..end]).map_err(|_| bad("the headers are not UTF-8"))?;
    let mut host = None;
    let mut origin = None;
    let mut length = None;
    for line in text.split('\n').skip(1) {
        let line = line.trim_end_matches('\r');
        if line.is_empty() {
            break;
        }
        if line.starts_with([' ', '\t']) {
            return Err(bad("folded header lines are not taken"));
        }
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
    // What was read past the headers is the body's first bytes.
    let mut body = Vec::with_capacity(length);
    body.extend_from_slice(&head[end..(end + length).min(head.len())]);
    let deadline = Instant::now() + shared.limits.body;
    while body.len() < length {
        let want = (length - body.len()).min(buf.len());
        let n = read_by(
            stream,
            deadline,
            &mut buf[..want],
            "the body was not sent in time",
        )?;
        if n == 0 {
            return Err(bad("the body is shorter than its Content-Length"));
        }
        body.extend_from_slice(&buf[..n]);
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
    // away, a little and for 200 ms at most in all, so that closing does
    // not reset the connection before the client has read the response.
    let until = Instant::now() + Duration::from_millis(200);
    let mut sink = [0u8; 16 * 1024];
    for _ in 0..64 {
        if read_by(stream, until, &mut sink, "").is_ok_and(|n| n > 0) {
            continue;
        }
        break;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Answers every request with its path; "done" ends the session.
    struct Echo;

    impl Handler for Echo {
        fn handle(&self, request: Request) -> Response {
            let mut r = Response::ok("text/plain", request.path.into_bytes());
            r.last = false;
            r
        }
        fn ended(&self) {}
    }

    fn start(limits: Limits) -> (u16, String) {
        let door = Door::open(0).unwrap().with_limits(limits);
        let (port, token) = (door.port, door.token.clone());
        let _ = door.serve(Arc::new(Echo));
        (port, token)
    }

    fn connect(port: u16) -> TcpStream {
        let s = TcpStream::connect(("127.0.0.1", port)).unwrap();
        // A guard against a hang, far above any answer's time.
        s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        s
    }

    /// The status of the response to `request`, read to its end.
    fn ask(port: u16, request: &str) -> (u16, String) {
        let mut s = connect(port);
        s.write_all(request.as_bytes()).unwrap();
        let mut answer = String::new();
        let _ = s.read_to_string(&mut answer);
        let status = answer
            .split(' ')
            .nth(1)
            .and_then(|c| c.parse().ok())
            .unwrap_or(0);
        (status, answer)
    }

    fn get(port: u16, token: &str, path: &str) -> String {
        format!("GET /{token}{path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n")
    }

    /// Asks for `path` up to `tries` times, `pause` apart, until the answer
    /// has `status`; the last status.
    fn ask_until(port: u16, token: &str, status: u16, tries: usize, pause: u64) -> u16 {
        let mut last = 0;
        for _ in 0..tries {
            last = ask(port, &get(port, token, "/w")).0;
            if last == status {
                break;
            }
            std::thread::sleep(Duration::from_millis(pause));
        }
        last
    }

    /// Whether the server has neither answered nor closed `s`.
    fn still_held(s: &TcpStream) -> bool {
        s.set_nonblocking(true).unwrap();
        let mut byte = [0u8; 1];
        let held =
            matches!(s.peek(&mut byte), Err(e) if e.kind() == std::io::ErrorKind::WouldBlock);
        s.set_nonblocking(false).unwrap();
        held
    }

    #[test]
    fn a_request_that_trickles_in_is_cut_off_at_its_deadline() {
        let head = Duration::from_millis(600);
        let (port, token) = start(Limits {
            head,
            ..Limits::default()
        });
        let request = get(port, &token, "/x");
        let mut s = connect(port);
        let begin = Instant::now();
        // A byte every 50 ms: each read is quick, the whole never ends.
        let mut sent = 0;
        for b in request.as_bytes()[..request.len() - 2].iter() {
            if s.write_all(&[*b]).is_err() {
                break;
            }
            sent += 1;
            std::thread::sleep(Duration::from_millis(50));
            if begin.elapsed() > head * 4 {
                break;
            }
        }
        let mut answer = String::new();
        let _ = s.read_to_string(&mut answer);
        assert!(answer.starts_with("HTTP/1.1 408"), "{answer:?}");
        // Cut off before the whole request was sent: the deadline counts
        // from the connection, not from each byte.
        assert!(
            sent < request.len() - 2,
            "{sent} of {} bytes",
            request.len()
        );
    }

    #[test]
    fn a_body_that_trickles_in_is_cut_off_at_its_deadline() {
        let (port, token) = start(Limits {
            body: Duration::from_millis(500),
            ..Limits::default()
        });
        let mut s = connect(port);
        let head = format!(
            "POST /{token}/x HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Length: 1000\r\n\r\n"
        );
        s.write_all(head.as_bytes()).unwrap();
        let mut sent = 0;
        while sent < 1000 && s.write_all(b"x").is_ok() {
            sent += 1;
            std::thread::sleep(Duration::from_millis(20));
            if !still_held(&s) {
                break;
            }
        }
        let mut answer = String::new();
        let _ = s.read_to_string(&mut answer);
        assert!(answer.starts_with("HTTP/1.1 408"), "{answer:?}");
        assert!(sent < 1000, "the whole body was taken");
    }

    #[test]
    fn a_client_with_the_token_is_answered_while_two_hundred_slow_ones_are_held() {
        let (port, token) = start(Limits::default());
        let mut held = Vec::new();
        for k in 0..200 {
            let mut s = connect(port);
            // Half send nothing, half the start of a request line (no token yet).
            if k % 2 == 1 {
                s.write_all(b"GET /").unwrap();
            }
            held.push(s);
        }
        // Some trickle on while the real client asks.
        for s in held.iter_mut().skip(1).step_by(2).take(20) {
            s.write_all(b"a").unwrap();
        }
        for k in 0..5 {
            let (status, answer) = ask(port, &get(port, &token, &format!("/page{k}")));
            assert_eq!(status, 200, "{answer}");
            assert!(answer.ends_with(&format!("/page{k}")), "{answer}");
        }
        // Answered while every slow connection was still held, not because
        // a deadline freed room.
        assert!(held.iter().all(still_held));
    }

    #[test]
    fn past_the_pending_cap_the_longest_waiting_connection_makes_room() {
        let (port, token) = start(Limits {
            pending: 8,
            ..Limits::default()
        });
        let held: Vec<TcpStream> = (0..20).map(|_| connect(port)).collect();
        let (status, answer) = ask(port, &get(port, &token, "/y"));
        assert_eq!(status, 200, "{answer}");
        // The first ones were closed (without an answer), the last ones wait.
        let mut byte = [0u8; 1];
        let first = (&held[0]).read(&mut byte);
        assert!(matches!(first, Ok(0)) || first.is_err(), "{first:?}");
        assert!(still_held(&held[19]));
    }

    #[test]
    fn a_slot_comes_back_when_its_deadline_passes_however_the_client_goes_on() {
        let (port, token) = start(Limits {
            head: Duration::from_millis(500),
            served: 1,
            ..Limits::default()
        });
        let mut slow = connect(port);
        slow.write_all(format!("GET /{token}/z HTTP/1.1\r\n").as_bytes())
            .unwrap();
        let mut writer = slow.try_clone().unwrap();
        // It goes on sending, past its 408, for longer than a test waits.
        std::thread::spawn(move || {
            for _ in 0..200 {
                let _ = writer.write_all(b"x");
                std::thread::sleep(Duration::from_millis(20));
            }
        });
        let mut answer = [0u8; 12];
        slow.read_exact(&mut answer).unwrap();
        assert_eq!(&answer, b"HTTP/1.1 408");
        // Its slot is free once the answer's short drain is over.
        assert_eq!(ask_until(port, &token, 200, 20, 50), 200);
    }

    #[test]
    fn connections_with_the_token_past_the_served_cap_get_503() {
        let (port, token) = start(Limits {
            served: 2,
            ..Limits::default()
        });
        let slow_one = || {
            let mut s = connect(port);
            s.write_all(format!("GET /{token}/z HTTP/1.1\r\n").as_bytes())
                .unwrap();
            s
        };
        let mut slow = vec![slow_one(), slow_one()];
        // Once the two have been read (the token seen), a third is refused.
        // (A third read before one of them takes its slot, and that one is
        // refused instead: it is replaced and the third asks again.)
        let mut status = 0;
        for _ in 0..200 {
            status = ask(port, &get(port, &token, "/w")).0;
            if status == 503 {
                break;
            }
            for s in &mut slow {
                if !still_held(s) {
                    *s = slow_one();
                }
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(status, 503);
        drop(slow);
        // Their slots come back once they are closed.
        assert_eq!(ask_until(port, &token, 200, 100, 20), 200);
    }
}
