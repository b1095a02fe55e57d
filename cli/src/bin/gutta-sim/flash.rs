//! `--flash DIR`: the simulated PLC's user flash in a directory, kept across restarts.
//! DIR holds `flash.bin` (gutta-sim's `persist` format), `flash.bin.tmp` while a commit
//! writes it, and `lock`, held while a simulator uses DIR. A commit is crash-safe: the
//! temp file written and fsynced, renamed over `flash.bin`, the directory fsynced; a
//! stale temp file is ignored (the next commit overwrites it). The format and the rules
//! of power-on are the library's; only the files are here.
//!
//! Fault injection for tests: `GUTTA_SIM_FLASH_PAUSE_MS=N` makes every commit write
//! half of the temp file, say so on stderr and pause N ms before it writes the rest
//! (a kill in the pause is a power cut in the middle of a commit); with
//! `GUTTA_SIM_FLASH_PAUSE_COMMIT=K` only the K-th commit of the process (from 1) pauses.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use gutta_cli::fatal::Fatal;
use gutta_sim::persist::{FlashImage, FlashStore};
use gutta_sim::plc::{FlashFault, Plc, PowerOn};

/// The flash file in DIR.
pub const FLASH_FILE: &str = "flash.bin";
/// Where a commit writes before its rename.
const TEMP_FILE: &str = "flash.bin.tmp";
/// The file a simulator holds locked while it uses DIR.
const LOCK_FILE: &str = "lock";
/// The fault-injection knobs (docs/simulator.md).
const PAUSE_VARIABLE: &str = "GUTTA_SIM_FLASH_PAUSE_MS";
const PAUSE_COMMIT_VARIABLE: &str = "GUTTA_SIM_FLASH_PAUSE_COMMIT";

/// What DIR held at start.
#[derive(Debug, Clone)]
pub enum Found {
    /// No flash file yet.
    Nothing,
    Flash(FlashImage),
    /// The flash file failed its check: why.
    Unreadable(String),
}

/// The flash of one PLC in DIR, locked for this process.
#[derive(Debug)]
pub struct FileStore {
    dir: PathBuf,
    /// Held (locked) while the store lives.
    _lock: File,
    pause: Option<Duration>,
    /// Only this commit (1-based) pauses; none: every one.
    pause_commit: Option<u64>,
    /// Commits so far.
    commits: u64,
}

/// Open DIR (created if missing), lock it, read its flash file.
pub fn open(dir: &Path) -> Result<(FileStore, Found), Fatal> {
    let shown = dir.display();
    std::fs::create_dir_all(dir)
        .map_err(|e| Fatal::io(format!("--flash {shown}: cannot create the directory: {e}")))?;
    let lock_path = dir.join(LOCK_FILE);
    let lock = File::options()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&lock_path)
        .map_err(|e| Fatal::io(format!("--flash {}: {e}", lock_path.display())))?;
    match lock.try_lock() {
        Ok(()) => {}
        Err(std::fs::TryLockError::WouldBlock) => {
            return Err(Fatal::io(format!(
                "--flash {shown}: another gutta-sim uses this flash ({} is locked)",
                lock_path.display()
            )))
        }
        Err(std::fs::TryLockError::Error(e)) => {
            return Err(Fatal::io(format!(
                "--flash {shown}: cannot lock {}: {e}",
                lock_path.display()
            )))
        }
    }
    let path = dir.join(FLASH_FILE);
    let found = match std::fs::read(&path) {
        Ok(bytes) => match FlashImage::decode(&bytes) {
            Ok(flash) => Found::Flash(flash),
            Err(e) => Found::Unreadable(e.to_string()),
        },
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Found::Nothing,
        Err(e) => return Err(Fatal::io(format!("--flash {}: {e}", path.display()))),
    };
    let number = |name: &str| {
        std::env::var(name)
            .ok()
            .map(|v| {
                v.parse::<u64>()
                    .map_err(|_| Fatal::usage(format!("{name}={v}: not a whole number")))
            })
            .transpose()
    };
    let store = FileStore {
        dir: dir.to_path_buf(),
        _lock: lock,
        pause: number(PAUSE_VARIABLE)?.map(Duration::from_millis),
        pause_commit: number(PAUSE_COMMIT_VARIABLE)?,
        commits: 0,
    };
    Ok((store, found))
}

impl Found {
    /// What the PLC powers on from: a flash, or (none yet) `seed`'s pages.
    pub fn power_on(&self, seed: Option<&gutta_format::Image>) -> PowerOn {
        match self {
            Found::Nothing => PowerOn::Fresh(seed.map(|i| i.pages.clone()).unwrap_or_default()),
            Found::Flash(flash) => PowerOn::Flash(flash.clone()),
            Found::Unreadable(why) => PowerOn::Unreadable(why.clone()),
        }
    }

    /// The PLC type the flash names, when it is readable.
    pub fn plc_type(&self) -> Option<&str> {
        match self {
            Found::Flash(flash) => Some(&flash.plc_type),
            _ => None,
        }
    }
}

impl FileStore {
    fn write_temp(&self, bytes: &[u8]) -> Result<(), String> {
        let temp = self.dir.join(TEMP_FILE);
        let fail =
            |what: &str, e: std::io::Error| format!("{}: cannot {what}: {e}", temp.display());
        let mut file = File::create(&temp).map_err(|e| fail("create", e))?;
        let half = bytes.len() / 2;
        file.write_all(&bytes[..half])
            .map_err(|e| fail("write", e))?;
        let this_one = self.pause_commit.is_none_or(|k| k == self.commits);
        if let Some(pause) = self.pause.filter(|_| this_one) {
            file.sync_data().map_err(|e| fail("sync", e))?;
            eprintln!(
                "gutta-sim: flash {}: paused {} ms in a commit ({PAUSE_VARIABLE})",
                self.dir.display(),
                pause.as_millis()
            );
            std::thread::sleep(pause);
        }
        file.write_all(&bytes[half..])
            .map_err(|e| fail("write", e))?;
        file.sync_all().map_err(|e| fail("sync", e))
    }

    /// The rename is durable once the directory's entry is: fsync the directory
    /// (Unix; elsewhere a directory cannot be opened as a file).
    fn sync_dir(&self) -> Result<(), String> {
        #[cfg(unix)]
        File::open(&self.dir)
            .and_then(|d| d.sync_all())
            .map_err(|e| format!("{}: cannot sync the directory: {e}", self.dir.display()))?;
        Ok(())
    }
}

impl FlashStore for FileStore {
    fn commit(&mut self, flash: &FlashImage) -> Result<(), String> {
        let bytes = flash.encode()?;
        self.commits += 1;
        self.write_temp(&bytes)?;
        let temp = self.dir.join(TEMP_FILE);
        let target = self.dir.join(FLASH_FILE);
        std::fs::rename(&temp, &target).map_err(|e| {
            format!(
                "cannot rename {} to {}: {e}",
                temp.display(),
                target.display()
            )
        })?;
        self.sync_dir()
    }
}

/// The start line saying what the flash held: (stderr?, text after `flash DIR: `).
pub fn describe(found: &Found, plc: &Plc, seeded: Option<&Path>) -> (bool, String) {
    if let Some(FlashFault::CheckFailed(why)) = plc.flash_fault() {
        let what = match found {
            Found::Unreadable(_) => "the flash file failed its check",
            _ => "the flash does not fit this PLC",
        };
        return (true, format!("{what} ({why}): no program"));
    }
    if let Some(FlashFault::DownloadInterrupted) = plc.flash_fault() {
        return (
            false,
            "cleared by an interrupted download: no program".into(),
        );
    }
    if plc.pages().is_empty() {
        return (false, "empty".into());
    }
    let state = if plc.vm().is_running() {
        "RUN"
    } else if plc.status_byte() & 0x08 != 0 {
        "STOP: the image does not verify"
    } else {
        "STOP"
    };
    let pages = plc.pages().len();
    let text = format!(
        "{} program, {pages} page{}, {state}",
        plc.target().name(),
        if pages == 1 { "" } else { "s" }
    );
    match seeded {
        Some(dir) => (false, format!("{text} (seeded from {})", dir.display())),
        None => (false, text),
    }
}

/// Whether DIR held a flash file (readable or not): it is kept, and an image given
/// with it is not loaded.
pub fn holds_a_flash(found: &Found) -> bool {
    !matches!(found, Found::Nothing)
}
