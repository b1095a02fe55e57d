//! `gutta-sim --device relay-board`: the simulated relay board (`gutta_sim::relay`) on
//! Modbus TCP listeners, Modbus TCP and the board's own frames on the same connection.
//! The I/O only: every connection shares one board; a change of its channels with
//! automatic reporting on sends the status frame on every open connection, after the
//! answer to the request that made it.

use std::future::Future;
use std::sync::{Arc, Mutex};

use gutta_cli::fatal::Fatal;
use gutta_sim::relay::{RelayBoard, RelaySession};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::sync::broadcast;

use crate::listen;

/// A status frame every connection sends.
type Report = [u8; 12];

/// Listens on `addresses` until `ctrl_c`.
pub async fn run(addresses: &[String], ctrl_c: impl Future<Output = ()>) -> Result<(), Fatal> {
    let board = Arc::new(Mutex::new(RelayBoard::default()));
    let (reports, _) = broadcast::channel::<Report>(64);
    let mut listeners = Vec::new();
    for address in addresses {
        listeners.push(listen::bind(address, "relay-board").await?);
    }
    for listener in listeners {
        let (board, reports) = (Arc::clone(&board), reports.clone());
        listen::accept_forever(listener, move |stream| {
            let receiver = reports.subscribe();
            serve(stream, Arc::clone(&board), reports.clone(), receiver)
        });
    }
    listen::until_ctrl_c(ctrl_c).await
}

/// One connection: answers its requests and passes on every report, until it closes
/// or sends a frame that is neither Modbus TCP nor the board's.
async fn serve(
    mut stream: TcpStream,
    board: Arc<Mutex<RelayBoard>>,
    reports: broadcast::Sender<Report>,
    mut incoming: broadcast::Receiver<Report>,
) {
    let mut session = RelaySession::new();
    let mut buf = vec![0u8; 4096];
    loop {
        tokio::select! {
            read = stream.read(&mut buf) => {
                let n = match read {
                    Ok(0) | Err(_) => return,
                    Ok(n) => n,
                };
                let (answer, report) = match board.lock() {
                    Ok(mut board) => {
                        let before = board.channels();
                        let answer = session.on_bytes(&mut board, &buf[..n]);
                        (answer, board.report(before))
                    }
                    Err(_) => return,
                };
                let answer = match answer {
                    Ok(answer) => answer,
                    Err(e) => {
                        eprintln!("gutta-sim: closing a connection: {e}");
                        if let Some(report) = report {
                            let _ = reports.send(report);
                        }
                        return;
                    }
                };
                if !answer.is_empty() && stream.write_all(&answer).await.is_err() {
                    return;
                }
                if let Some(report) = report {
                    let _ = reports.send(report);
                }
            }
            report = incoming.recv() => match report {
                Ok(report) => {
                    if stream.write_all(&report).await.is_err() {
                        return;
                    }
                }
                Err(broadcast::error::RecvError::Lagged(_)) => {}
                Err(broadcast::error::RecvError::Closed) => return,
            },
        }
    }
}
