//! The one TCP accept loop of `gutta-sim`, for every device it simulates (the PLC's
//! Modbus TCP and RTU-over-TCP listeners, `--device relay-board`, `--device fx`):
//! binding and announcing a listener, accepting, spawning one task per connection,
//! riding out a failed accept, and the Ctrl-C stop line. What a connection does is the
//! caller's (a closure per accepted stream); no protocol here.

use std::future::Future;
use std::net::SocketAddr;
use std::time::Duration;

use gutta_cli::fatal::Fatal;
use tokio::net::{TcpListener, TcpStream};

use crate::say;

/// How long the loop waits after a failed accept (out of file descriptors, say) before
/// it accepts again, so a lasting failure does not spin.
const ACCEPT_RETRY: Duration = Duration::from_millis(100);

/// Binds `address` and says `gutta-sim: {kind} on {local address}` on stdout once it
/// listens (port 0 picks a free port, which the line names).
pub async fn bind(address: &str, kind: &str) -> Result<TcpListener, Fatal> {
    let (listener, local) = bind_silently(address).await?;
    say(&format!("gutta-sim: {kind} on {local}"));
    Ok(listener)
}

/// Binds `address` and says nothing: the listener and the address it listens on (a
/// plant says every listener of a device on one line).
pub async fn bind_silently(address: &str) -> Result<(TcpListener, SocketAddr), Fatal> {
    let listener = TcpListener::bind(address)
        .await
        .map_err(|e| Fatal::io(format!("cannot listen on {address}: {e}")))?;
    let local = listener
        .local_addr()
        .map_err(|e| Fatal::io(format!("{address}: {e}")))?;
    Ok((listener, local))
}

/// Accepts connections on `listener` in a task of its own for the life of the process:
/// each stream (Nagle off, answers are small) goes to `serve`, whose future runs in a
/// task of its own. `serve` itself runs at accept time, so what it does before its
/// future starts (a subscription, say) sees the connection in accept order. A failed
/// accept is said on stderr and retried after [`ACCEPT_RETRY`].
pub fn accept_forever<F, Fut>(listener: TcpListener, serve: F)
where
    F: Fn(TcpStream) -> Fut + Send + 'static,
    Fut: Future<Output = ()> + Send + 'static,
{
    tokio::spawn(async move {
        loop {
            match listener.accept().await {
                Ok((stream, _)) => {
                    let _ = stream.set_nodelay(true);
                    tokio::spawn(serve(stream));
                }
                Err(e) => {
                    eprintln!("gutta-sim: accept failed: {e}");
                    tokio::time::sleep(ACCEPT_RETRY).await;
                }
            }
        }
    });
}

/// What stopped the simulator: Ctrl-C (SIGINT) or SIGTERM; both are a clean stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StoppedBy {
    CtrlC,
    Sigterm,
}

/// Waits for `ctrl_c` (Ctrl-C or SIGTERM) and says the simulator stopped: a clean stop
/// (the help's exit status 0).
pub async fn until_ctrl_c(ctrl_c: impl Future<Output = StoppedBy>) -> Result<(), Fatal> {
    let by = ctrl_c.await;
    stopped(by)
}

/// The stop line, `gutta-sim: stopped by Ctrl-C` (or `by SIGTERM`), for a caller that
/// waits on the signal in its own loop (the PLC's scans).
pub fn stopped(by: StoppedBy) -> Result<(), Fatal> {
    say(match by {
        StoppedBy::CtrlC => "gutta-sim: stopped by Ctrl-C",
        StoppedBy::Sigterm => "gutta-sim: stopped by SIGTERM",
    });
    Ok(())
}
