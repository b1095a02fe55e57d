//! The client against a real `gutta-sim` process: a download over Modbus TCP and over
//! RTU over TCP, then status, run/stop and variables; an upload that writes the
//! downloaded image directory byte for byte; a download refused for another PLC type.
//! The simulator binary is the workspace's (built by `cargo test --workspace`).

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::{Image, Operand, PackedOperand};
use gutta_link::transport::{rtu_over_tcp, TcpTransport};
use gutta_link::{download, upload, Client, LinkError, FACTORY_PASSWORD};

const POINTERS: &str = include_str!("../../examples/in1001_pointers.lad");
/// Every kind of page: MAIN, an interrupt, a subroutine, data blocks, a system block.
const BLINK: &str = include_str!("../../examples/blink.lad");

struct Sim {
    child: Child,
    tcp: String,
    rtu: String,
}

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// An empty simulated PLC of `plc`.
fn start(plc: &str) -> Sim {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args([
            "--plc",
            plc,
            "--tcp",
            "127.0.0.1:0",
            "--rtu-tcp",
            "127.0.0.1:0",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts gutta-sim");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let mut addr = || {
        let line = lines.next().expect("listener").expect("text");
        line.rsplit(' ').next().expect("address").to_string()
    };
    let tcp = addr();
    let rtu = addr();
    Sim { child, tcp, rtu }
}

fn image(plc: &str) -> Image {
    compiled(plc, POINTERS)
}

fn compiled(plc: &str, text: &str) -> Image {
    let target = stdlib::shared(plc).expect("target");
    compile(
        SourceFile::new("p.lad", text),
        Some(&ExplicitTarget {
            target,
            origin: "test".into(),
        }),
    )
    .image
    .expect("compiles")
}

/// The packed address of MW`offset` on CPU-EC20.
fn mw(offset: u32) -> u32 {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let a = target
        .memory
        .parse_address(&format!("MW{offset}"))
        .expect("address");
    PackedOperand::encode(Operand::Value(a)).0
}

fn exercise(client: &mut Client) {
    let image = image("CPU-EC20");
    let pack = stdlib::shared("CPU-EC20")
        .expect("target")
        .plc
        .exch_pack_size as usize;
    let mut sent = 0;
    let report =
        download(client, &image, &FACTORY_PASSWORD, pack, &mut |n| sent += n).expect("downloads");
    assert_eq!(report.pages, image.pages.len());
    // Progress counts every byte written and every byte read back.
    assert_eq!(sent, 2 * report.bytes);
    // After the reset: log in again, the program runs.
    client.attach(&FACTORY_PASSWORD).expect("login");
    std::thread::sleep(std::time::Duration::from_millis(100));
    assert_eq!(
        client.status().expect("status") & 0b1101,
        0b0101,
        "RUN, ATTACH, no ERROR"
    );
    let values = client.read_vars(&[mw(24)]).expect("read");
    assert_eq!(
        values[0],
        [0x01, 0x0E, 0x02, 0x0E],
        "MW24 = 16#0E01, MW26 = 16#0E02"
    );
    client.set_running(false).expect("stop");
    assert_eq!(client.status().expect("status") & 1, 0);
    client
        .write_vars(&[(mw(40), 0xBEEF)], false)
        .expect("write");
    assert_eq!(
        client.read_vars(&[mw(40)]).expect("read")[0][..2],
        [0xEF, 0xBE]
    );
    client.set_running(true).expect("run");
    // Forcing M is refused (only I and Q).
    assert!(matches!(
        client.write_vars(&[(mw(40), 1)], true),
        Err(LinkError::Refused {
            function: 0x0A21,
            ..
        })
    ));
}

#[test]
fn download_and_operate_over_modbus_tcp() {
    let sim = start("CPU-EC20");
    let transport = TcpTransport::connect(&sim.tcp, 1000, 2).expect("connects");
    exercise(&mut Client::new(Box::new(transport), 1));
}

#[test]
fn download_and_operate_over_rtu_over_tcp() {
    let sim = start("CPU-EC20");
    let transport = rtu_over_tcp(&sim.rtu, 1000, 2).expect("connects");
    exercise(&mut Client::new(Box::new(transport), 1));
}

/// Every file under `dir`, by its path relative to `dir` with `/` separators.
fn files_under(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    gutta_io::directory_files(dir).expect("a readable directory")
}

#[test]
fn an_upload_writes_the_downloaded_image_directory_byte_for_byte() {
    let sim = start("CPU-EC20");
    let transport = TcpTransport::connect(&sim.tcp, 1000, 2).expect("connects");
    let mut client = Client::new(Box::new(transport), 1);
    let image = compiled("CPU-EC20", BLINK);
    let pack = stdlib::shared("CPU-EC20")
        .expect("target")
        .plc
        .exch_pack_size as usize;
    let scratch = |tag: &str| {
        let dir =
            std::env::temp_dir().join(format!("gutta-link-upload-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    };
    let (sent_dir, back_dir) = (scratch("sent"), scratch("back"));
    gutta_io::write_image(&sent_dir, &image).expect("writes the image");
    download(&mut client, &image, &FACTORY_PASSWORD, pack, &mut |_| {}).expect("downloads");
    // The image's system block sets the password the PLC asks for from now on.
    let uploaded = upload(
        &mut client,
        &gutta_format::password_bytes(Some("1234")),
        pack,
    )
    .expect("uploads");
    gutta_io::write_image(&back_dir, &uploaded).expect("writes the upload");
    let (sent, back) = (files_under(&sent_dir), files_under(&back_dir));
    let _ = std::fs::remove_dir_all(&sent_dir);
    let _ = std::fs::remove_dir_all(&back_dir);
    // Every page kind is there, so the directory is more than a manifest and a const page.
    for file in [
        gutta_format::MANIFEST_FILE,
        "const.bin",
        "argument/00.bin",
        "instruction/00.bin",
        "data/0.bin",
        "system/0.bin",
    ] {
        assert!(sent.contains_key(file), "{file} in {:?}", sent.keys());
    }
    assert_eq!(sent.len(), image.pages.len() + 1, "{:?}", sent.keys());
    assert_eq!(
        back.keys().collect::<Vec<_>>(),
        sent.keys().collect::<Vec<_>>(),
        "the same files"
    );
    assert_eq!(
        String::from_utf8_lossy(&back[gutta_format::MANIFEST_FILE]),
        String::from_utf8_lossy(&sent[gutta_format::MANIFEST_FILE])
    );
    for (name, bytes) in &sent {
        assert_eq!(&back[name], bytes, "{name}");
    }
}

#[test]
fn a_download_for_another_plc_type_is_refused_before_anything_changes() {
    let sim = start("CPU-EC20");
    let transport = TcpTransport::connect(&sim.tcp, 1000, 2).expect("connects");
    let mut client = Client::new(Box::new(transport), 1);
    let other = image("EC30-EK51");
    let err =
        download(&mut client, &other, &FACTORY_PASSWORD, 64, &mut |_| {}).expect_err("refused");
    assert_eq!(
        err,
        LinkError::WrongPlc {
            plc: "CPU-EC20".into(),
            image: "EC30-EK51".into()
        }
    );
    // A wrong password is refused with the login's failure.
    assert!(matches!(
        client.attach(&[0; 16]),
        Err(LinkError::Refused {
            function: 0x0110,
            ..
        })
    ));
}

#[test]
fn a_client_that_disconnects_mid_download_leaves_a_stopped_plc_and_a_serving_server() {
    let sim = start("CPU-EC20");
    let image = image("CPU-EC20");
    {
        let transport = TcpTransport::connect(&sim.tcp, 1000, 2).expect("connects");
        let mut client = Client::new(Box::new(transport), 1);
        client.attach(&FACTORY_PASSWORD).expect("login");
        client.clear().expect("clear");
        let (id, page) = image.pages.iter().next().expect("a page");
        client
            .write_page(*id, &page[..page.len().min(10)], 64, &mut |_| {})
            .expect("one packet");
        // The client goes away here, mid-download.
    }
    let transport = TcpTransport::connect(&sim.tcp, 1000, 2).expect("connects again");
    let mut client = Client::new(Box::new(transport), 1);
    client.attach(&FACTORY_PASSWORD).expect("login");
    assert_eq!(
        client.status().expect("status") & 1,
        0,
        "not running half an image"
    );
    download(&mut client, &image, &FACTORY_PASSWORD, 64, &mut |_| {})
        .expect("a new download works");
    client.attach(&FACTORY_PASSWORD).expect("login");
    std::thread::sleep(std::time::Duration::from_millis(100));
    assert_eq!(
        client.status().expect("status") & 1,
        1,
        "runs the whole image"
    );
}

#[test]
fn a_system_block_moves_the_station_at_reset_and_clear_moves_it_back() {
    let sim = start("CPU-EC20");
    let rtu = |station| {
        Client::new(
            Box::new(rtu_over_tcp(&sim.rtu, 300, 0).expect("connects")),
            station,
        )
    };
    // blink's system block says station 20 and password 1234. The download writes it
    // while the PLC still answers at 1 (it takes effect at the reset) and reads every
    // page back there.
    let mut client = rtu(1);
    download(
        &mut client,
        &compiled("CPU-EC20", BLINK),
        &FACTORY_PASSWORD,
        64,
        &mut |_| {},
    )
    .expect("downloads at station 1");
    let password = gutta_format::password_bytes(Some("1234"));
    assert!(
        matches!(rtu(1).attach(&password), Err(LinkError::Timeout { .. })),
        "station 1 is silent after the reset"
    );
    let mut at_20 = rtu(20);
    at_20.attach(&password).expect("logs in at station 20");
    assert_eq!(at_20.status().expect("status") & 1, 1, "RUN");
    // Downloading from station 20: PLC_CLEAR sends the PLC back to station 1 and the
    // client follows it there.
    download(&mut at_20, &image("CPU-EC20"), &password, 64, &mut |_| {})
        .expect("downloads from station 20");
    assert_eq!(at_20.station(), 1);
    let mut at_1 = rtu(1);
    at_1.attach(&FACTORY_PASSWORD).expect("station 1 again");
    assert_eq!(at_1.status().expect("status") & 1, 1, "RUN");
}
