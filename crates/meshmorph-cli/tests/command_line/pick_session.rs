//! A `meshmorph pick` session for tests: two procedural surfaces, the
//! command started on them, its address read from its first line, and raw
//! HTTP requests to it. Shared by the tests of the door (`pick_door.rs`)
//! and the page's check in Chromium (`external/pick_page.rs`).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use meshmorph::Mesh3;

/// The height of the bumpy sheet at `(x, y)`, scaled by `scale`.
pub fn height(x: f64, y: f64, scale: f64) -> f64 {
    0.08 * scale * ((1.7 * x / scale).sin() + (1.3 * y / scale).cos())
}

/// A bumpy square sheet over `[-scale, scale]²`, `n` quads a side, each
/// split in two, facing +z.
pub fn sheet(n: usize, scale: f64) -> Mesh3 {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let x = scale * (2.0 * i as f64 / n as f64 - 1.0);
            let y = scale * (2.0 * j as f64 / n as f64 - 1.0);
            positions.push([x, y, height(x, y, scale)]);
        }
    }
    let v = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            triangles.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            triangles.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    Mesh3::new(positions, triangles).expect("a valid sheet")
}

/// A running `meshmorph pick`.
// Each of the two test binaries that use it reads some of its fields.
#[allow(dead_code)]
pub struct Pick {
    pub child: Child,
    pub url: String,
    pub port: u16,
    pub token: String,
    pub source: PathBuf,
    pub target: PathBuf,
    pub output: PathBuf,
}

// The page's check uses neither raw request.
#[allow(dead_code)]
impl Pick {
    /// Writes the two sheets (the target finer and larger) into `dir` and
    /// starts `pick` on them, saving to `dir/markers.txt`.
    pub fn start(dir: &Path, extra: &[&str]) -> Pick {
        let source = dir.join("source.obj");
        let target = dir.join("target.obj");
        meshmorph::io::write_mesh(&source, &sheet(16, 1.0), meshmorph::io::Format::Obj).unwrap();
        meshmorph::io::write_mesh(&target, &sheet(24, 1.5), meshmorph::io::Format::Obj).unwrap();
        let output = dir.join("markers.txt");
        Self::spawn(&[&source, &target], output, extra)
    }

    /// Writes the demo's arm sprite, straight and bent by 150° (with its
    /// anchors, `anchors.txt`), into `dir` and starts `pick` on the two
    /// pictures, saving to `dir/picked.txt`.
    pub fn start_pictures(dir: &Path, extra: &[&str]) -> Pick {
        use meshmorph::io::picture::{arm_anchors, arm_sprite, ARM_SPRITE_SIZE};
        let bend = 150f64.to_radians();
        let source = dir.join("arm-straight.png");
        let target = dir.join("arm-bent.png");
        for (path, angle) in [(&source, 0.0), (&target, bend)] {
            let mut file = std::fs::File::create(path).unwrap();
            meshmorph::render::write_picture_png(&mut file, &arm_sprite(angle, ARM_SPRITE_SIZE))
                .unwrap();
        }
        let mut text = String::new();
        for (name, a, b) in arm_anchors(bend, ARM_SPRITE_SIZE) {
            text.push_str(&format!("{name} {} {} {} {}\n", a[0], a[1], b[0], b[1]));
        }
        std::fs::write(dir.join("anchors.txt"), text).unwrap();
        Self::spawn(&[&source, &target], dir.join("picked.txt"), extra)
    }

    /// `pick --template TEMPLATE HEAD -o dir/landmarks.txt`.
    pub fn start_guided(dir: &Path, template: &str, head: &Path) -> Pick {
        let output = dir.join("landmarks.txt");
        Self::spawn(&[head], output, &["--template", template])
    }

    /// `pick MESHES -o OUTPUT EXTRA`, its address read from its first line.
    fn spawn(meshes: &[&Path], output: PathBuf, extra: &[&str]) -> Pick {
        let (source, target) = (
            meshes[0].to_path_buf(),
            meshes[meshes.len() - 1].to_path_buf(),
        );
        let mut child = Command::new(env!("CARGO_BIN_EXE_meshmorph"))
            .arg("pick")
            .args(meshes)
            .arg("-o")
            .arg(&output)
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("meshmorph runs");
        let mut line = String::new();
        BufReader::new(child.stdout.as_mut().unwrap())
            .read_line(&mut line)
            .unwrap();
        let url = line
            .split_whitespace()
            .find(|w| w.starts_with("http://"))
            .unwrap_or_else(|| panic!("no address in {line:?}"))
            .to_string();
        let rest = url.strip_prefix("http://127.0.0.1:").unwrap();
        let (port, token) = rest.split_once('/').unwrap();
        Pick {
            child,
            port: port.parse().unwrap(),
            token: token.trim_end_matches('/').to_string(),
            url,
            source,
            target,
            output,
        }
    }

    /// Sends `raw` (a whole request) and returns the status and body.
    pub fn send(&self, raw: &[u8]) -> (u16, String) {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .unwrap();
        let _ = stream.write_all(raw);
        Self::answer(stream)
    }

    /// The status and body of the response on `stream`.
    fn answer(stream: TcpStream) -> (u16, String) {
        let (status, body) = Self::answer_bytes(stream);
        (status, String::from_utf8_lossy(&body).into_owned())
    }

    /// The status and body (as bytes) of the response on `stream`.
    fn answer_bytes(mut stream: TcpStream) -> (u16, Vec<u8>) {
        let mut answer = Vec::new();
        let _ = stream.read_to_end(&mut answer);
        let end = answer
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .map_or(answer.len(), |k| k + 4);
        let head = String::from_utf8_lossy(&answer[..end]).into_owned();
        let status = head
            .split_whitespace()
            .nth(1)
            .and_then(|s| s.parse().ok())
            .unwrap_or(0);
        (status, answer[end..].to_vec())
    }

    /// [`Pick::page`] with the body as bytes (a picture).
    pub fn page_bytes(&self, method: &str, path: &str, body: &str) -> (u16, Vec<u8>) {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .unwrap();
        let _ = stream.write_all(self.request(method, path, body).as_bytes());
        Self::answer_bytes(stream)
    }

    /// A request from the page itself: the right Host, Origin and token.
    pub fn page(&self, method: &str, path: &str, body: &str) -> (u16, String) {
        self.send(self.request(method, path, body).as_bytes())
    }

    /// The whole of a request from the page.
    fn request(&self, method: &str, path: &str, body: &str) -> String {
        let host = format!("127.0.0.1:{}", self.port);
        format!(
            "{method} /{}{path} HTTP/1.1\r\nHost: {host}\r\nOrigin: http://{host}\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
            self.token,
            body.len()
        )
    }

    /// [`Pick::page`] sent in parts of 64 KiB, telling `started` once the
    /// first part is sent.
    pub fn page_in_parts(
        &self,
        method: &str,
        path: &str,
        body: &str,
        started: std::sync::mpsc::Sender<()>,
    ) -> (u16, String) {
        let raw = self.request(method, path, body);
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .unwrap();
        for (k, part) in raw.as_bytes().chunks(64 * 1024).enumerate() {
            if stream.write_all(part).is_err() {
                break;
            }
            if k == 0 {
                let _ = started.send(());
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        Self::answer(stream)
    }

    /// Waits for the process to end (after "done"), at most a minute.
    pub fn wait(&mut self) -> std::process::ExitStatus {
        for _ in 0..600 {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        panic!("pick did not stop");
    }
}

impl Drop for Pick {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
