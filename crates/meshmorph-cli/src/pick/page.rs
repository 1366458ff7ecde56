//! The page of `meshmorph pick` and what it loads, built into the program:
//! nothing is fetched from elsewhere, and it works offline.
//!
//! `page/vendor` holds three.js (`three.module.js`, `three.core.js`,
//! `OrbitControls.js` and its licence) exactly as the `three` package that
//! `tools/browser-checks/package-lock.json` pins ships them; a test checks
//! that they are the same bytes. `OrbitControls.js` imports `'three'` by
//! name, which a page resolves with an import map; it is served with that
//! one import pointed at `./three.module.js` instead, so that the page needs
//! no inline script (its Content-Security-Policy allows none).

use std::sync::OnceLock;

/// A file of the page.
pub struct Asset {
    pub content_type: &'static str,
    pub body: &'static [u8],
}

const JS: &str = "text/javascript; charset=utf-8";

/// The file at `path` (after the token), if the page has one there.
pub fn asset(path: &str) -> Option<Asset> {
    let (content_type, body): (&str, &'static [u8]) = match path {
        "/" | "/index.html" => (
            "text/html; charset=utf-8",
            include_bytes!("page/index.html"),
        ),
        "/pick.css" => ("text/css; charset=utf-8", include_bytes!("page/pick.css")),
        "/pick.js" => (JS, include_bytes!("page/pick.js")),
        "/server.js" => (JS, include_bytes!("page/server.js")),
        "/three.module.js" => (JS, include_bytes!("page/vendor/three.module.js")),
        "/three.core.js" => (JS, include_bytes!("page/vendor/three.core.js")),
        "/OrbitControls.js" => (JS, orbit_controls()),
        _ => return None,
    };
    Some(Asset { content_type, body })
}

/// The file at `path` of the page for two pictures (`pick A.png B.png`),
/// if it has one there.
pub fn picture_asset(path: &str) -> Option<Asset> {
    let (content_type, body): (&str, &'static [u8]) = match path {
        "/" | "/index.html" => (
            "text/html; charset=utf-8",
            include_bytes!("page/pictures.html"),
        ),
        "/pick.css" => ("text/css; charset=utf-8", include_bytes!("page/pick.css")),
        "/pictures.css" => (
            "text/css; charset=utf-8",
            include_bytes!("page/pictures.css"),
        ),
        "/pictures.js" => (JS, include_bytes!("page/pictures.js")),
        "/server.js" => (JS, include_bytes!("page/server.js")),
        _ => return None,
    };
    Some(Asset { content_type, body })
}

/// `OrbitControls.js` importing three.js by its path on this server.
fn orbit_controls() -> &'static [u8] {
    static SERVED: OnceLock<Vec<u8>> = OnceLock::new();
    SERVED.get_or_init(|| {
        String::from_utf8_lossy(include_bytes!("page/vendor/OrbitControls.js"))
            .replacen("from 'three';", "from './three.module.js';", 1)
            .into_bytes()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_controls_imports_three_by_path() {
        let text = String::from_utf8_lossy(orbit_controls()).into_owned();
        assert!(text.contains("from './three.module.js';"));
        assert!(!text.contains("from 'three';"));
    }

    #[test]
    fn every_file_the_page_names_is_served() {
        let html = String::from_utf8_lossy(asset("/").unwrap().body).into_owned();
        for name in ["pick.css", "pick.js"] {
            assert!(html.contains(name), "{name}");
            assert!(asset(&format!("/{name}")).is_some());
        }
        let js = String::from_utf8_lossy(asset("/pick.js").unwrap().body).into_owned();
        for name in ["./three.module.js", "./OrbitControls.js", "./server.js"] {
            assert!(js.contains(name), "{name}");
            assert!(asset(&name[1..]).is_some());
        }
        assert!(asset("/../Cargo.toml").is_none());
        let html = String::from_utf8_lossy(picture_asset("/").unwrap().body).into_owned();
        for name in ["pick.css", "pictures.css", "pictures.js"] {
            assert!(html.contains(name), "{name}");
            assert!(picture_asset(&format!("/{name}")).is_some());
        }
        assert!(picture_asset("/pick.js").is_none());
        let js = String::from_utf8_lossy(picture_asset("/pictures.js").unwrap().body).into_owned();
        assert!(js.contains("./server.js") && picture_asset("/server.js").is_some());
        assert!(asset("/vendor/LICENSE").is_none());
    }
}
