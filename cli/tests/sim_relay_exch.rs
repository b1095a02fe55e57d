//! The relay board switched by a PLC, end to end with two `gutta-sim` processes (issue
//! 16): the PLC runs examples/exch_relay_board.lad with `--port0 modbus-tcp:` leading to
//! `gutta-sim --device relay-board`. The PLC's inputs are set with `gutta-cc write`; the
//! board's channels follow, read by mbpoll as an independent Modbus TCP client (channel
//! n is coil 16#0200 + n - 1, mbpoll's reference 513 + n - 1), and what the PLC reads back
//! from the board lands in its M1.0..M1.3.

mod common;

use std::time::{Duration, Instant};

use common::Sim;

fn start(args: &[&str]) -> Sim {
    common::sim_on_free_port(args)
}

fn read(address: &str, var: &str) -> u32 {
    common::read_number(address, var)
}

/// Polls until (the board's channels, the PLC's MB1) is `want`, or 5 s pass.
fn settle(plc: &str, board: &str, want: (u32, u32)) -> (u32, u32) {
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let now = (common::relay_channels(board), read(plc, "MB1"));
        if now == want || Instant::now() > deadline {
            return now;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn the_boards_channels_follow_the_plcs_inputs_through_the_gateway() {
    if !common::have("mbpoll") {
        return;
    }
    let image = common::image_dir("exch_relay_board", &common::example("exch_relay_board.lad"));
    let board = start(&["--device", "relay-board"]);
    let image = image.display().to_string();
    let plc = start(&[&image, "--port0", &format!("modbus-tcp:{}", board.1)]);

    let write = |assignments: &[&str]| {
        let mut args = vec!["write", "--tcp", plc.1.as_str()];
        args.extend_from_slice(assignments);
        let out = common::cc(&args);
        assert!(out.status.success(), "{}", common::text(&out));
    };
    write(&["I0.0=1", "I0.2=1"]);
    assert_eq!(
        settle(&plc.1, &board.1, (0b0101, 0b0101)),
        (0b0101, 0b0101),
        "channels 1..4 follow I0.0..I0.3; the PLC reads them back into M1.0..M1.3"
    );
    write(&["I0.0=0", "I0.1=1", "I0.3=1"]);
    assert_eq!(settle(&plc.1, &board.1, (0b1110, 0b1110)), (0b1110, 0b1110));
    // Every exchange answered: the read's and the report switch's error bytes stay 0.
    assert_eq!(read(&plc.1, "MB81"), 0);
    assert_eq!(read(&plc.1, "MB113"), 0);
}
