//! Who may talk to the studio (docs/studio.md, "The server"): a random token per run,
//! required on every request (query `token=`, header `X-Gutta-Token`, or
//! `Authorization: Bearer`) and compared in constant time, and no request from another
//! page's origin. It decides only who asks, never which files (`files.rs`).

use std::net::SocketAddr;

use axum::http::{header, HeaderMap, Uri};

use super::refusal::Refusal;

/// The bytes of randomness in a token (32 hex digits).
const TOKEN_BYTES: usize = 16;

/// This run's secret.
#[derive(Clone)]
pub(crate) struct Token(String);

impl Token {
    /// A token from the operating system's random source (`getrandom`: the
    /// `getrandom` call or /dev/urandom on Linux, `ProcessPrng` on Windows, ...).
    pub(crate) fn generate() -> std::io::Result<Token> {
        let mut bytes = [0u8; TOKEN_BYTES];
        getrandom::fill(&mut bytes).map_err(|e| std::io::Error::other(e.to_string()))?;
        Ok(Token(bytes.iter().map(|b| format!("{b:02x}")).collect()))
    }

    pub(crate) fn as_str(&self) -> &str {
        &self.0
    }

    /// Whether `given` is this token, in time that does not depend on where they differ.
    fn matches(&self, given: &str) -> bool {
        let (ours, theirs) = (self.0.as_bytes(), given.as_bytes());
        if ours.len() != theirs.len() {
            return false;
        }
        ours.iter()
            .zip(theirs)
            .fold(0u8, |acc, (a, b)| acc | (a ^ b))
            == 0
    }
}

/// The checks every request passes before any handler runs.
#[derive(Clone)]
pub(crate) struct Guard {
    token: Token,
    /// The origins of the studio's own page (`http://127.0.0.1:PORT`, and
    /// `http://localhost:PORT` on loopback).
    origins: Vec<String>,
    /// Bound to every interface (`0.0.0.0`, `::`): the page's origin is the address the
    /// browser used, which the request's `Host` names.
    any_interface: bool,
}

impl Guard {
    pub(crate) fn new(token: Token, at: SocketAddr) -> Guard {
        let mut origins = vec![format!("http://{at}")];
        if at.ip().is_loopback() {
            origins.push(format!("http://localhost:{}", at.port()));
        }
        Guard {
            token,
            origins,
            any_interface: at.ip().is_unspecified(),
        }
    }

    /// A request's origin, then its token.
    pub(crate) fn check(&self, headers: &HeaderMap, uri: &Uri) -> Result<(), Refusal> {
        if let Some(origin) = headers.get(header::ORIGIN) {
            let origin = origin.to_str().unwrap_or("(not text)");
            if !self.own_origin(origin, headers) {
                return Err(Refusal::OriginForeign(origin.to_string()));
            }
        }
        let given = request_token(headers, uri).ok_or(Refusal::TokenMissing)?;
        if self.token.matches(&given) {
            Ok(())
        } else {
            Err(Refusal::TokenWrong)
        }
    }

    fn own_origin(&self, origin: &str, headers: &HeaderMap) -> bool {
        if self.origins.iter().any(|o| o.eq_ignore_ascii_case(origin)) {
            return true;
        }
        self.any_interface
            && headers
                .get(header::HOST)
                .and_then(|h| h.to_str().ok())
                .is_some_and(|host| origin.eq_ignore_ascii_case(&format!("http://{host}")))
    }
}

/// The token a request carries: the query's `token=`, else `X-Gutta-Token`, else
/// `Authorization: Bearer`.
fn request_token(headers: &HeaderMap, uri: &Uri) -> Option<String> {
    if let Some(token) = query_value(uri, "token") {
        return Some(token);
    }
    if let Some(token) = headers.get("x-gutta-token").and_then(|v| v.to_str().ok()) {
        return Some(token.trim().to_string());
    }
    let authorization = headers.get(header::AUTHORIZATION)?.to_str().ok()?;
    let (scheme, token) = authorization.trim().split_once(' ')?;
    scheme
        .eq_ignore_ascii_case("bearer")
        .then(|| token.trim().to_string())
}

/// The first value of `name` in the request's query, percent-decoded (`+` a blank);
/// `None` when absent or not UTF-8 once decoded.
pub(crate) fn query_value(uri: &Uri, name: &str) -> Option<String> {
    uri.query()?.split('&').find_map(|pair| {
        let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
        (percent_decode(key)? == name).then(|| percent_decode(value))?
    })
}

fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'+' => out.push(b' '),
            b'%' => {
                let hex = text.get(i + 1..i + 3)?;
                out.push(u8::from_str_radix(hex, 16).ok()?);
                i += 2;
            }
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn guard() -> Guard {
        Guard::new(Token("00ff".repeat(8)), "127.0.0.1:4000".parse().unwrap())
    }

    #[test]
    fn tokens_are_32_hex_digits_and_differ_per_run() {
        let (a, b) = (Token::generate().unwrap(), Token::generate().unwrap());
        assert_eq!(a.as_str().len(), 32);
        assert!(a.as_str().bytes().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(a.as_str(), b.as_str());
    }

    #[test]
    fn the_token_comes_from_the_query_or_a_header() {
        let g = guard();
        let good = "00ff".repeat(8);
        let uri: Uri = format!("/api/file?path=a.lad&token={good}")
            .parse()
            .unwrap();
        assert_eq!(g.check(&HeaderMap::new(), &uri), Ok(()));
        let bare: Uri = "/".parse().unwrap();
        assert_eq!(
            g.check(&HeaderMap::new(), &bare),
            Err(Refusal::TokenMissing)
        );
        let mut headers = HeaderMap::new();
        headers.insert("x-gutta-token", good.parse().unwrap());
        assert_eq!(g.check(&headers, &bare), Ok(()));
        let mut headers = HeaderMap::new();
        headers.insert(
            header::AUTHORIZATION,
            format!("Bearer {good}").parse().unwrap(),
        );
        assert_eq!(g.check(&headers, &bare), Ok(()));
        let wrong: Uri = format!("/?token={}", "00fe".repeat(8)).parse().unwrap();
        assert_eq!(g.check(&HeaderMap::new(), &wrong), Err(Refusal::TokenWrong));
        let short: Uri = "/?token=00ff".parse().unwrap();
        assert_eq!(g.check(&HeaderMap::new(), &short), Err(Refusal::TokenWrong));
    }

    #[test]
    fn only_the_studios_own_origin_passes() {
        let g = guard();
        let uri: Uri = format!("/?token={}", "00ff".repeat(8)).parse().unwrap();
        for (origin, ok) in [
            ("http://127.0.0.1:4000", true),
            ("http://localhost:4000", true),
            ("http://127.0.0.1:4001", false),
            ("https://evil.example", false),
            ("null", false),
        ] {
            let mut headers = HeaderMap::new();
            headers.insert(header::ORIGIN, origin.parse().unwrap());
            assert_eq!(g.check(&headers, &uri).is_ok(), ok, "{origin}");
        }
    }

    #[test]
    fn query_values_are_percent_decoded() {
        let uri: Uri = "/x?path=src%2Fmain.lad&a=b+c&bad=%zz".parse().unwrap();
        assert_eq!(query_value(&uri, "path").as_deref(), Some("src/main.lad"));
        assert_eq!(query_value(&uri, "a").as_deref(), Some("b c"));
        assert_eq!(query_value(&uri, "bad"), None);
        assert_eq!(query_value(&uri, "none"), None);
    }
}
