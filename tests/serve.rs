//! `lumiere serve`: the web build's files over HTTP with the
//! cross-origin-isolation headers, their media types, and nothing outside
//! the folder.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::Command;

mod common;

use common::Served;

/// The status line and headers (lower-case names) and the body of `method target`.
fn get(server: &Served, method: &str, target: &str) -> (String, Vec<(String, String)>, Vec<u8>) {
    let mut stream = TcpStream::connect(("127.0.0.1", server.port)).unwrap();
    write!(stream, "{method} {target} HTTP/1.1\r\nHost: x\r\n\r\n").unwrap();
    let mut answer = Vec::new();
    stream.read_to_end(&mut answer).unwrap();
    let split = answer.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    let head = String::from_utf8(answer[..split].to_vec()).unwrap();
    let mut lines = head.lines();
    let status = lines.next().unwrap().to_string();
    let headers = lines
        .filter_map(|l| l.split_once(": "))
        .map(|(k, v)| (k.to_lowercase(), v.to_string()))
        .collect();
    (status, headers, answer[split + 4..].to_vec())
}

fn header<'a>(headers: &'a [(String, String)], name: &str) -> Option<&'a str> {
    headers
        .iter()
        .find(|(k, _)| k == name)
        .map(|(_, v)| v.as_str())
}

#[test]
fn the_site_is_served_cross_origin_isolated_and_confined_to_its_folder() {
    let root = std::env::temp_dir().join(format!("lumiere-serve-{}", std::process::id()));
    let site = root.join("site");
    std::fs::create_dir_all(site.join("pkg")).unwrap();
    std::fs::write(site.join("index.html"), "<!doctype html><p>lumiere</p>").unwrap();
    std::fs::write(site.join("pkg/lumiere_bg.wasm"), b"\0asm\x01\0\0\0").unwrap();
    std::fs::write(root.join("secret.txt"), "outside").unwrap();
    let server = Served::start(&site);

    let (status, headers, body) = get(&server, "GET", "/");
    assert_eq!(status, "HTTP/1.1 200 OK");
    assert_eq!(body, b"<!doctype html><p>lumiere</p>");
    assert_eq!(
        header(&headers, "content-type"),
        Some("text/html; charset=utf-8")
    );
    assert_eq!(
        header(&headers, "cross-origin-opener-policy"),
        Some("same-origin")
    );
    assert_eq!(
        header(&headers, "cross-origin-embedder-policy"),
        Some("require-corp")
    );

    let (status, headers, body) = get(&server, "GET", "/pkg/lumiere_bg.wasm?v=1");
    assert_eq!(status, "HTTP/1.1 200 OK");
    assert_eq!(header(&headers, "content-type"), Some("application/wasm"));
    assert_eq!(body.len(), 8);

    let (status, headers, body) = get(&server, "HEAD", "/index.html");
    assert_eq!(status, "HTTP/1.1 200 OK");
    assert_eq!(header(&headers, "content-length"), Some("29"));
    assert!(body.is_empty());

    for outside in [
        "/../secret.txt",
        "/%2e%2e/secret.txt",
        "/pkg/../../secret.txt",
        "/missing.js",
    ] {
        let (status, _, body) = get(&server, "GET", outside);
        assert_eq!(status, "HTTP/1.1 404 Not Found", "{outside}");
        assert!(!String::from_utf8_lossy(&body).contains("outside"));
    }
    let (status, _, _) = get(&server, "POST", "/");
    assert_eq!(status, "HTTP/1.1 405 Method Not Allowed");
    drop(server);

    // --no-isolation: the same files, as a plain static host serves them
    let plain = Served::start_with(&site, &["--no-isolation"]);
    let (status, headers, body) = get(&plain, "GET", "/");
    assert_eq!(status, "HTTP/1.1 200 OK");
    assert_eq!(body, b"<!doctype html><p>lumiere</p>");
    assert_eq!(header(&headers, "cross-origin-opener-policy"), None);
    assert_eq!(header(&headers, "cross-origin-embedder-policy"), None);
    drop(plain);
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn a_folder_without_a_site_is_refused_by_name() {
    let empty = std::env::temp_dir().join(format!("lumiere-serve-empty-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    for folder in [empty.clone(), empty.join("missing")] {
        let out = Command::new(env!("CARGO_BIN_EXE_lumiere"))
            .args(["serve", "--port", "0"])
            .arg(&folder)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(&*folder.display().to_string()), "{stderr}");
    }
    std::fs::remove_dir_all(&empty).unwrap();
}
