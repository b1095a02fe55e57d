//! The one way `gutta-cc monitor` and `gutta-cc studio` serve HTTP: a two-thread tokio
//! runtime, a listener bound on `--http`, the router made once the address is known
//! (the caller prints its lines and builds its routes then), served until Ctrl-C.

use std::net::SocketAddr;

use gutta_cli::fatal::Fatal;

/// Bind `http`, call `app` with the bound address (a free port resolved), and serve its
/// router until Ctrl-C. A runtime or an address that fails is an I/O error before
/// `app` runs, so nothing was printed.
pub(crate) fn until_ctrl_c(
    http: &str,
    app: impl FnOnce(SocketAddr) -> axum::Router,
) -> Result<(), Fatal> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| Fatal::io(format!("cannot start the HTTP server: {e}")))?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(http)
            .await
            .map_err(|e| Fatal::io(format!("--http {http}: {e}")))?;
        let at = listener
            .local_addr()
            .map_err(|e| Fatal::io(format!("--http {http}: {e}")))?;
        axum::serve(listener, app(at))
            .with_graceful_shutdown(async {
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
            .map_err(|e| Fatal::io(format!("HTTP server: {e}")))
    })
}
