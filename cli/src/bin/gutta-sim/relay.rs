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
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::broadcast;

use crate::say;

/// A status frame every connection sends.
type Report = [u8; 12];

/// Listens on `addresses` until `ctrl_c`.
pub async fn run(addresses: &[String], ctrl_c: impl Future<Output = ()>) -> Result<(), Fatal> {
    let board = Arc::new(Mutex::new(RelayBoard::default()));
    let (reports, _) = broadcast::channel::<Report>(64);
    let mut listeners = Vec::new();
    for address in addresses {
        let listener = TcpListener::bind(address)
            .await
            .map_err(|e| Fatal::io(format!("cannot listen on {address}: {e}")))?;
        let local = listener
            .local_addr()
            .map_err(|e| Fatal::io(format!("{address}: {e}")))?;
        say(&format!("gutta-sim: relay-board on {local}"));
        listeners.push(listener);
    }
    for listener in listeners {
        let (board, reports) = (Arc::clone(&board), reports.clone());
        tokio::spawn(async move {
            loop {
                match listener.accept().await {
                    Ok((stream, _)) => {
                        let _ = stream.set_nodelay(true);
                        let receiver = reports.subscribe();
                        tokio::spawn(serve(stream, Arc::clone(&board), reports.clone(), receiver));
                    }
                    Err(e) => {
                        eprintln!("gutta-sim: accept failed: {e}");
                        tokio::time::sleep(std::time::Duration::from_millis(100)).await;
                    }
                }
            }
        });
    }
    ctrl_c.await;
    say("gutta-sim: stopped by Ctrl-C");
    Ok(())
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
