//! `gutta-sim --device relay-board`: the simulated relay board (`gutta_sim::relay`) on
//! Modbus TCP listeners, Modbus TCP and the board's own frames on the same connection.
//! The I/O only: every connection shares one board; a change of its channels with
//! automatic reporting on sends the status frame on every open connection, after the
//! answer to the request that made it. A plant's board ([`Board`]) is served the same
//! way, and its in-process line feeds the same [`Board::on_bytes`].

use std::future::Future;
use std::sync::{Arc, Mutex};

use gutta_cli::fatal::Fatal;
use gutta_sim::relay::{RelayBoard, RelaySession};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::broadcast;

use crate::listen;

/// A status frame every connection sends.
type Report = [u8; 12];

/// One simulated board: its channels, shared by every connection (and by a plant's PLC
/// port that leads to it), and the status frames its changes send to every connection.
#[derive(Debug, Clone)]
pub struct Board {
    board: Arc<Mutex<RelayBoard>>,
    reports: broadcast::Sender<Report>,
}

impl Board {
    pub fn new() -> Board {
        Board {
            board: Arc::new(Mutex::new(RelayBoard::default())),
            reports: broadcast::channel::<Report>(64).0,
        }
    }

    /// Serves the board on `listener` for the life of the process.
    pub fn accept(&self, listener: TcpListener) {
        let board = self.clone();
        listen::accept_forever(listener, move |stream| {
            let receiver = board.reports.subscribe();
            serve(stream, board.clone(), receiver)
        });
    }

    /// Bytes of `session` in (Modbus TCP or the board's own frames), its answers out;
    /// a change of the channels with automatic reporting on sends the status frame to
    /// every connection (after this answer: a connection sends what it reads in order).
    /// An error says why the session must end.
    pub fn on_bytes(&self, session: &mut RelaySession, bytes: &[u8]) -> Result<Vec<u8>, String> {
        let (answer, report) = match self.board.lock() {
            Ok(mut board) => {
                let before = board.channels();
                let answer = session.on_bytes(&mut board, bytes);
                (answer, board.report(before))
            }
            Err(_) => return Err("the relay board's state was poisoned by a panic".into()),
        };
        if let Some(report) = report {
            let _ = self.reports.send(report);
        }
        answer.map_err(|e| e.to_string())
    }
}

/// Listens on `addresses` until `ctrl_c`.
pub async fn run(
    addresses: &[String],
    ctrl_c: impl Future<Output = listen::StoppedBy>,
) -> Result<(), Fatal> {
    let board = Board::new();
    let mut listeners = Vec::new();
    for address in addresses {
        listeners.push(listen::bind(address, "relay-board").await?);
    }
    for listener in listeners {
        board.accept(listener);
    }
    listen::until_ctrl_c(ctrl_c).await
}

/// One connection: answers its requests and passes on every report, until it closes
/// or sends a frame that is neither Modbus TCP nor the board's.
async fn serve(mut stream: TcpStream, board: Board, mut incoming: broadcast::Receiver<Report>) {
    let mut session = RelaySession::new();
    let mut buf = vec![0u8; 4096];
    loop {
        tokio::select! {
            read = stream.read(&mut buf) => {
                let n = match read {
                    Ok(0) | Err(_) => return,
                    Ok(n) => n,
                };
                let answer = match board.on_bytes(&mut session, &buf[..n]) {
                    Ok(answer) => answer,
                    Err(e) => {
                        eprintln!("gutta-sim: closing a connection: {e}");
                        return;
                    }
                };
                if !answer.is_empty() && stream.write_all(&answer).await.is_err() {
                    return;
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
