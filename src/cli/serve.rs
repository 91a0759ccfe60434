//! `lumiere serve`: the web build's folder over HTTP on 127.0.0.1, with the
//! cross-origin-isolation headers the page's threads need.
//!
//! The page renders on Web Workers that share the WebAssembly memory, which
//! a browser allows only to a cross-origin-isolated page: every response
//! carries `Cross-Origin-Opener-Policy: same-origin` and
//! `Cross-Origin-Embedder-Policy: require-corp`. A plain static server
//! without them gives a page that renders on one thread (it says so);
//! `--no-isolation` serves the folder so, to see that page.
//!
//! A small HTTP/1.1 server for GET and HEAD of files in one folder: one
//! thread per connection, no keep-alive, paths inside the folder only.

use std::io::{BufRead, BufReader, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Component, Path, PathBuf};

use anyhow::Context;
use clap::Args;

use crate::cli::Failure;

#[derive(Args)]
pub struct ServeArgs {
    /// The folder `bash .ci/build-web OUT` wrote.
    pub folder: PathBuf,
    /// Port on 127.0.0.1 (0: any free port, printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// Without the cross-origin-isolation headers, as a plain static host
    /// serves files: the page then renders on one thread.
    #[arg(long)]
    pub no_isolation: bool,
}

/// Serves the folder until the process is stopped.
pub fn run(args: &ServeArgs) -> Result<(), Failure> {
    let root = args
        .folder
        .canonicalize()
        .with_context(|| format!("{}: no such folder", args.folder.display()))
        .map_err(Failure::usage)?;
    if !root.join("index.html").is_file() {
        return Err(Failure::usage_message(format_args!(
            "{}: no index.html (build the site with `bash .ci/build-web {}`)",
            args.folder.display(),
            args.folder.display()
        )));
    }
    let listener = TcpListener::bind(("127.0.0.1", args.port))
        .with_context(|| format!("cannot listen on 127.0.0.1:{}", args.port))
        .map_err(Failure::runtime)?;
    let port = listener.local_addr().map_err(Failure::runtime)?.port();
    println!(
        "serving {} at http://127.0.0.1:{port}/ (Ctrl+C stops)",
        root.display()
    );
    let isolation = !args.no_isolation;
    for stream in listener.incoming().flatten() {
        let root = root.clone();
        std::thread::spawn(move || {
            // a client that goes away mid-answer is not an error of the server
            let _ = answer(stream, &root, isolation);
        });
    }
    Ok(())
}

/// Reads one request and answers it, with the isolation headers if `isolation`.
fn answer(stream: TcpStream, root: &Path, isolation: bool) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut request_line = String::new();
    reader.read_line(&mut request_line)?;
    // the headers: read and ignored
    let mut line = String::new();
    while reader.read_line(&mut line)? > 2 {
        line.clear();
    }
    let mut parts = request_line.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    let mut stream = stream;
    let headers = if isolation { ISOLATION } else { "" };
    if method != "GET" && method != "HEAD" {
        return respond(
            &mut stream,
            "405 Method Not Allowed",
            "text/plain",
            b"GET or HEAD only\n",
            method == "HEAD",
            headers,
        );
    }
    let head = method == "HEAD";
    match file_of(root, target).and_then(|path| Some((std::fs::read(&path).ok()?, path))) {
        Some((body, path)) => respond(
            &mut stream,
            "200 OK",
            content_type(&path),
            &body,
            head,
            headers,
        ),
        None => respond(
            &mut stream,
            "404 Not Found",
            "text/plain",
            b"not found\n",
            head,
            headers,
        ),
    }
}

/// The file of the folder a request target names (`/` is `index.html`);
/// `None` for a target outside the folder or not a file.
pub fn file_of(root: &Path, target: &str) -> Option<PathBuf> {
    let path = target.split(['?', '#']).next().unwrap_or("");
    let path = percent_encoding::percent_decode_str(path)
        .decode_utf8()
        .ok()?;
    let relative = Path::new(path.trim_start_matches('/'));
    if relative
        .components()
        .any(|c| !matches!(c, Component::Normal(_)))
    {
        return None;
    }
    let mut file = root.join(relative);
    if file.is_dir() {
        file = file.join("index.html");
    }
    // a link inside the folder may not lead out of it
    let file = file.canonicalize().ok()?;
    (file.starts_with(root) && file.is_file()).then_some(file)
}

/// The media type of a file of the site, by its extension.
pub fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()).unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "wasm" => "application/wasm",
        "css" => "text/css; charset=utf-8",
        "json" | "gltf" => "application/json",
        "glb" => "model/gltf-binary",
        "png" => "image/png",
        "toml" | "md" | "txt" => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

/// The headers that make the page cross-origin isolated.
const ISOLATION: &str = "Cross-Origin-Opener-Policy: same-origin\r\n\
                         Cross-Origin-Embedder-Policy: require-corp\r\n";

/// Writes the answer; `headers` are more header lines, each ending in CRLF.
fn respond(
    stream: &mut TcpStream,
    status: &str,
    content_type: &str,
    body: &[u8],
    head: bool,
    headers: &str,
) -> std::io::Result<()> {
    write!(
        stream,
        "HTTP/1.1 {status}\r\n\
         Content-Type: {content_type}\r\n\
         Content-Length: {}\r\n\
         {headers}\
         Cache-Control: no-cache\r\n\
         Connection: close\r\n\r\n",
        body.len()
    )?;
    if !head {
        stream.write_all(body)?;
    }
    stream.flush()
}
