//! Tables (ATT, FIFO, LIFO, FND=, FND<>, FND<, FND>).

use super::Handler;

pub fn lookup(_mnemonic: &str) -> Option<Handler> {
    None
}
