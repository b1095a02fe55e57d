//! gutta-link's `Session` against a simulated PLC in the same process: the login with
//! the password lookup and the injected prompt, typed reads batched by ExchPackSize
//! (the requests counted) and cut to their widths, writes in requests by the packet
//! size, forces and unforce.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use gutta_compiler::{compile, source::SourceFile};
use gutta_format::SymbolTable;
use gutta_link::session::is_wrong_password;
use gutta_link::{
    var, Answer, Client, Credentials, LinkError, LoginError, NoPrompt, Session, Transport,
};
use gutta_sim::plc::{ConnectionId, Plc};

/// A PLC in the same process; `requests` counts the request PDUs it answered.
#[derive(Debug)]
struct InProcess {
    plc: Plc,
    requests: Arc<AtomicUsize>,
}

impl Transport for InProcess {
    fn exchange(&mut self, _station: u8, pdu: &[u8]) -> Result<Answer, LinkError> {
        self.requests.fetch_add(1, Ordering::Relaxed);
        let pdu = gutta_sim::session::answer(&mut self.plc, ConnectionId(1), pdu, 0);
        Ok(Answer::from_pdu(pdu))
    }
}

const PROGRAM: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.0
MOVW   3585, MW24
END_ORGANIZATION_BLOCK
";

/// A client of a running CPU-EC20 (ExchPackSize 64: 16 reads or 8 writes a request)
/// with `source`, and its request counter.
fn running(source: &str) -> (Client, Arc<AtomicUsize>) {
    let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT).expect("target");
    let image = compile(SourceFile::new("main.lad", source), None)
        .image
        .expect("the program compiles");
    let mut plc = Plc::new(Arc::clone(&target), image.pages, Default::default()).expect("plc");
    plc.scan().expect("a scan");
    let requests = Arc::new(AtomicUsize::new(0));
    let transport = InProcess {
        plc,
        requests: Arc::clone(&requests),
    };
    (Client::new(Box::new(transport), 1), requests)
}

fn session() -> (Session, Arc<AtomicUsize>) {
    let (client, requests) = running(PROGRAM);
    let mut session = Session::log_in(
        client,
        "in process",
        &Credentials::lookup(None, None),
        &mut NoPrompt,
    )
    .expect("the factory password logs in");
    let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT).expect("target");
    session.set_target(&target);
    (session, requests)
}

fn vars(texts: &[&str]) -> Vec<gutta_link::Var> {
    let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT).expect("target");
    texts
        .iter()
        .map(|t| var::resolve(t, &SymbolTable::default(), &target).expect("a variable"))
        .collect()
}

#[test]
fn reads_are_cut_to_their_width_and_batched_by_the_packet_size() {
    let (mut session, requests) = session();
    let read = vars(&["MW24", "MB24", "MB25", "M24.0", "M24.1", "MD24:hex"]);
    let before = requests.load(Ordering::Relaxed);
    let values = session.read(&read).expect("read");
    // MW24 = 3585 = 16#0E01, little-endian in memory: MB24 is 01, MB25 0E.
    assert_eq!(values[..5], [3585, 0x01, 0x0E, 1, 0]);
    assert_eq!(values[5] & 0xFFFF, 3585);
    assert_eq!(
        requests.load(Ordering::Relaxed) - before,
        1,
        "one window, one read"
    );
    assert_eq!(session.var_reads(), 1);
    // 25 words 4 bytes apart: 25 windows, 16 a request.
    let many: Vec<String> = (0..25).map(|i| format!("MW{}", 4 * i)).collect();
    let many: Vec<&str> = many.iter().map(String::as_str).collect();
    let values = session.read(&vars(&many)).expect("read");
    assert_eq!(values.len(), 25);
    assert_eq!(values[6], 3585, "MW24");
    assert_eq!(session.var_reads(), 1 + 2);
}

#[test]
fn writes_forces_and_unforce_take_typed_variables() {
    let (mut session, _) = session();
    let written: Vec<(gutta_link::Var, u32)> = vars(&["MW40", "MB50", "M60.3"])
        .into_iter()
        .zip([0xBEEF, 0x7F, 1])
        .collect();
    session.write(&written).expect("write");
    let read: Vec<gutta_link::Var> = written.iter().map(|(v, _)| v.clone()).collect();
    assert_eq!(session.read(&read).expect("read"), [0xBEEF, 0x7F, 1]);
    // More pairs than one request holds (8 at ExchPackSize 64) go in several.
    let many: Vec<String> = (0..20).map(|i| format!("MW{}", 70 + 2 * i)).collect();
    let many = vars(&many.iter().map(String::as_str).collect::<Vec<_>>());
    let pairs: Vec<(gutta_link::Var, u32)> = many.iter().cloned().zip(1..).collect();
    session.write(&pairs).expect("write");
    let back = session.read(&many).expect("read");
    assert_eq!(back, (1..=20).collect::<Vec<u32>>());
    // Only I and Q can be forced; a force shows in the force values until released.
    let q = vars(&["Q0.1"]);
    assert!(session
        .force(&vars(&["MW40"]).into_iter().zip([1]).collect::<Vec<_>>())
        .is_err());
    session
        .force(&q.iter().cloned().zip([1]).collect::<Vec<_>>())
        .expect("force");
    let address = [q[0].address];
    assert_eq!(session.read_forces(&address).expect("forces"), [1]);
    // The release sends the value the variable has now, and returns it.
    assert_eq!(session.unforce(&q).expect("unforce"), [1]);
}

#[test]
fn a_refused_factory_password_asks_the_prompt_once() {
    let source = format!("{PROGRAM}\nSYSTEM_BLOCK\n  PASSWORD = \"s3cret\"\nEND_SYSTEM_BLOCK\n");
    let (client, _) = running(&source);
    let factory = Credentials::lookup(None, Some(""));
    let mut asked = Vec::new();
    let mut prompt = |endpoint: &str| -> Result<Option<String>, String> {
        asked.push(endpoint.to_string());
        Ok(Some("s3cret".to_string()))
    };
    let session = Session::log_in(client, "127.0.0.1:502", &factory, &mut prompt)
        .expect("the typed password logs in");
    assert_eq!(asked, ["127.0.0.1:502"]);
    assert_eq!(
        session.password(),
        gutta_format::password_bytes(Some("s3cret"))
    );

    // Nobody to ask: the PLC's refusal.
    let (client, _) = running(&source);
    match Session::log_in(client, "x", &factory, &mut NoPrompt) {
        Err(LoginError::PasswordNeeded(e)) => assert!(is_wrong_password(&e)),
        other => panic!("expected PasswordNeeded, got {other:?}"),
    }
    // A wrong password from the environment is not retried at a prompt.
    let (client, _) = running(&source);
    let mut never = |_: &str| -> Result<Option<String>, String> { panic!("no prompt") };
    let wrong = Credentials::lookup(None, Some("nope"));
    match Session::log_in(client, "x", &wrong, &mut never) {
        Err(LoginError::Link(e)) => assert!(is_wrong_password(&e)),
        other => panic!("expected a refusal, got {other:?}"),
    }
}
