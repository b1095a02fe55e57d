//! A real `gutta-cc studio --no-open` for the tests that talk to its JSON routes
//! (`studio_sim.rs`, `studio_online.rs`): started on a folder, its address and token
//! read from the first line, killed when dropped; `call` sends one request with the
//! token and reads the status and the JSON answer over a plain std TcpStream.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use serde_json::Value;

/// A running studio, killed when dropped.
pub struct Studio {
    child: Child,
    /// `127.0.0.1:PORT`.
    pub address: String,
    pub token: String,
}

impl Drop for Studio {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Studio {
    /// `gutta-cc studio --no-open DIR` in `dir` (without `GUTTA_PASSWORD`), until its
    /// first line.
    pub fn start(dir: &Path) -> Studio {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
            .args(["studio", "--no-open"])
            .arg(dir)
            .current_dir(dir)
            .env_remove("GUTTA_PASSWORD")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("gutta-cc studio starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("stdout"))
            .read_line(&mut line)
            .expect("the first line");
        let rest = line
            .trim_end()
            .strip_prefix("gutta-cc studio: http://")
            .unwrap_or_else(|| panic!("first line: {line:?}"));
        let (address, token) = rest.split_once("/?token=").expect("the token");
        Studio {
            address: address.to_string(),
            token: token.to_string(),
            child,
        }
    }

    /// `METHOD PATH` with the token and `body` as JSON: the status and the JSON answer.
    pub fn call(&self, method: &str, path: &str, body: &str) -> (u16, Value) {
        let mut stream = TcpStream::connect(&self.address).expect("connects");
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .expect("timeout");
        let text = format!(
            "{method} {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nX-Gutta-Token: {}\r\n\
             Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
            self.address,
            self.token,
            body.len()
        );
        stream.write_all(text.as_bytes()).expect("sends");
        let mut answer = Vec::new();
        stream.read_to_end(&mut answer).expect("reads the answer");
        let answer = String::from_utf8_lossy(&answer).into_owned();
        let (head, body) = answer.split_once("\r\n\r\n").expect("a head and a body");
        let status = head
            .split(' ')
            .nth(1)
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("status line: {head}"));
        let json = serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {body}"));
        (status, json)
    }
}
