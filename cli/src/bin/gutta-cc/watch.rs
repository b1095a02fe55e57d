//! `gutta-cc watch VAR...`: sample variables every `--interval` and show them: a live
//! table on a terminal (crossterm, alternate screen, restored on every exit), one line
//! per sample when stdout is not a terminal, one JSON object per sample with `--json`,
//! one sample with `--once`. Resolving variables belongs to `gutta_cli::vars`, reading
//! them to gutta-link's `Session` (through `client.rs`); this file only samples and draws.

use std::io::{IsTerminal, Write};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use crossterm::event::{self, Event, KeyCode, KeyEvent, KeyModifiers};
use crossterm::{cursor, queue, terminal};
use gutta_cli::fatal::Fatal;
use gutta_link::Session;
use serde_json::json;

use crate::args::LinkArgs;
use crate::client::{self, Online};
use gutta_cli::vars::{Var, VarJson};

pub(crate) struct Options {
    pub interval_ms: u64,
    pub once: bool,
    pub json: bool,
}

/// The variables, their last values and when each last changed.
struct Sampler {
    session: Session,
    vars: Vec<Var>,
    values: Vec<u32>,
    changed: Vec<Option<Instant>>,
    /// When the first sample's values arrived: time 0 of `time_ms`.
    start: Instant,
    /// When the latest sample's values arrived.
    sampled: Instant,
    samples: u64,
}

impl Sampler {
    /// Read every variable (in as few requests as the protocol allows).
    fn sample(&mut self) -> Result<(), Fatal> {
        let now = self.session.read(&self.vars).map_err(|e| {
            Fatal::link(format!(
                "lost the connection to the PLC after {}: {e}",
                gutta_cli::plural::count(self.samples, "sample")
            ))
        })?;
        if self.samples > 0 {
            for (i, (old, new)) in self.values.iter().zip(&now).enumerate() {
                if old != new {
                    self.changed[i] = Some(Instant::now());
                }
            }
        }
        self.values = now;
        self.sampled = Instant::now();
        if self.samples == 0 {
            self.start = self.sampled;
        }
        self.samples += 1;
        Ok(())
    }

    /// The latest sample's time, counted from the first sample (whose is 0).
    fn time_ms(&self) -> u128 {
        self.sampled.duration_since(self.start).as_millis()
    }

    /// `{"time_ms", "values": [{"name", "address", "format", "value", "raw"}]}`.
    fn json(&self) -> serde_json::Value {
        json!({
            "time_ms": self.time_ms(),
            "values": self.vars.iter().zip(&self.values).map(|(v, r)| v.json(*r)).collect::<Vec<_>>(),
        })
    }

    /// `1.400 s: Lamp (Q0.0) = 1, MW10 = -5`.
    fn line(&self) -> String {
        let values: Vec<String> = self
            .vars
            .iter()
            .zip(&self.values)
            .map(|(v, r)| format!("{} = {}", v.label(), v.show(*r)))
            .collect();
        format!(
            "{:.3} s: {}",
            self.time_ms() as f64 / 1000.0,
            values.join(", ")
        )
    }

    /// The table: a header and one row per variable, columns aligned.
    fn table(&self) -> Vec<String> {
        let mut rows = vec![[
            "NAME".to_string(),
            "ADDRESS".into(),
            "FORMAT".into(),
            "VALUE".into(),
            "CHANGED".into(),
        ]];
        for (i, v) in self.vars.iter().enumerate() {
            let changed = match self.changed[i] {
                Some(at) => format!("{:.1} s ago", at.elapsed().as_secs_f64()),
                None => "-".into(),
            };
            rows.push([
                v.symbol.clone().unwrap_or_else(|| "-".into()),
                v.canonical.clone(),
                v.format.name().into(),
                v.show(self.values[i]),
                changed,
            ]);
        }
        let widths: Vec<usize> = (0..5)
            .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
            .collect();
        rows.iter()
            .map(|r| {
                let cells: Vec<String> = r
                    .iter()
                    .zip(&widths)
                    .map(|(cell, w)| format!("{cell:<w$}"))
                    .collect();
                cells.join("  ").trim_end().to_string()
            })
            .collect()
    }
}

pub(crate) fn watch(
    online: &Online,
    vars: &[String],
    options: &Options,
    link: &LinkArgs,
) -> Result<ExitCode, Fatal> {
    let (session, vars) = client::login_with_vars(online, vars, link)?;
    let n = vars.len();
    let mut sampler = Sampler {
        session,
        vars,
        values: vec![0; n],
        changed: vec![None; n],
        start: Instant::now(),
        sampled: Instant::now(),
        samples: 0,
    };
    let interval = Duration::from_millis(options.interval_ms.max(1));
    let terminal = std::io::stdout().is_terminal();
    if !options.json && !options.once && terminal {
        return live(&mut sampler, interval, link);
    }
    let mut out = std::io::stdout().lock();
    loop {
        let next = Instant::now() + interval;
        sampler.sample()?;
        let text = if options.json {
            sampler.json().to_string()
        } else if options.once {
            sampler.table().join("\n")
        } else {
            sampler.line()
        };
        // A closed pipe (`| head`) ends the watch quietly.
        if writeln!(out, "{text}").and_then(|()| out.flush()).is_err() || options.once {
            return Ok(ExitCode::SUCCESS);
        }
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
}

/// The terminal in raw mode on the alternate screen, put back when dropped (on quit, on
/// an error and on a panic's unwinding alike).
struct Screen;

impl Screen {
    fn enter() -> Result<Screen, Fatal> {
        let fail = |e: std::io::Error| Fatal::io(format!("cannot drive the terminal: {e}"));
        terminal::enable_raw_mode().map_err(fail)?;
        let screen = Screen;
        crossterm::execute!(
            std::io::stdout(),
            terminal::EnterAlternateScreen,
            cursor::Hide
        )
        .map_err(fail)?;
        Ok(screen)
    }
}

impl Drop for Screen {
    fn drop(&mut self) {
        let _ = crossterm::execute!(
            std::io::stdout(),
            cursor::Show,
            terminal::LeaveAlternateScreen
        );
        let _ = terminal::disable_raw_mode();
    }
}

/// The live table until q, Esc or Ctrl-C; a lost connection ends it with the terminal
/// restored, then the error.
fn live(sampler: &mut Sampler, interval: Duration, link: &LinkArgs) -> Result<ExitCode, Fatal> {
    let screen = Screen::enter()?;
    let plc = client::link_config(link)?.address().to_string();
    let result = (|| -> Result<(), Fatal> {
        loop {
            let next = Instant::now() + interval;
            sampler.sample()?;
            draw(sampler, &plc, interval)?;
            loop {
                let left = next.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    break;
                }
                let ready = event::poll(left).map_err(terminal_error)?;
                if !ready {
                    break;
                }
                match event::read().map_err(terminal_error)? {
                    Event::Key(key) if quits(key) => return Ok(()),
                    Event::Resize(..) => draw(sampler, &plc, interval)?,
                    _ => {}
                }
            }
        }
    })();
    drop(screen);
    result.map(|()| ExitCode::SUCCESS)
}

fn terminal_error(e: std::io::Error) -> Fatal {
    Fatal::io(format!("terminal: {e}"))
}

fn quits(key: KeyEvent) -> bool {
    matches!(key.code, KeyCode::Char('q') | KeyCode::Esc)
        || (key.code == KeyCode::Char('c') && key.modifiers.contains(KeyModifiers::CONTROL))
}

/// One frame: a title, the table cut to the terminal's size, a hint at the bottom.
fn draw(sampler: &Sampler, plc: &str, interval: Duration) -> Result<(), Fatal> {
    let (width, height) = terminal::size().map_err(terminal_error)?;
    let (width, height) = (usize::from(width), usize::from(height).max(3));
    let mut lines = vec![format!(
        "gutta-cc watch: {plc} every {} ms, sample {}",
        interval.as_millis(),
        sampler.samples
    )];
    lines.extend(sampler.table());
    let room = height - 1;
    if lines.len() > room {
        let hidden = lines.len() - room + 1;
        lines.truncate(room - 1);
        lines.push(format!("... {hidden} more rows: enlarge the terminal"));
    }
    let mut out = std::io::stdout().lock();
    queue!(out, terminal::Clear(terminal::ClearType::All)).map_err(terminal_error)?;
    for (row, line) in lines.iter().enumerate() {
        let cut: String = line.chars().take(width).collect();
        queue!(
            out,
            cursor::MoveTo(0, row as u16),
            crossterm::style::Print(cut)
        )
        .map_err(terminal_error)?;
    }
    let hint: String = "q, Esc or Ctrl-C: quit".chars().take(width).collect();
    queue!(
        out,
        cursor::MoveTo(0, (height - 1) as u16),
        crossterm::style::Print(hint)
    )
    .map_err(terminal_error)?;
    out.flush().map_err(terminal_error)
}
