//! Passwords off the command line, through the real binaries: a `gutta-sim` whose image
//! sets a password (its SYSTEM_BLOCK), and `gutta-cc status` logging in with
//! GUTTA_PASSWORD, with --password, with neither (no terminal: a message naming both;
//! a terminal under tmux: a prompt that does not echo), and the wrong-password and
//! lockout messages, which must differ. The prompt's test needs tmux.

mod common;

use common::{stderr, Sim};

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

const PASSWORD: &str = "s3cret";
const PASSWORD_ENV: &str = "GUTTA_PASSWORD";
const REFUSED: &str = "refused: wrong password";
const LOCKED: &str = "locked: the PLC refuses logins";

/// A simulated CPU-EC20 that runs a program whose system block sets PASSWORD.
fn sim(tag: &str) -> Sim {
    let source = format!(
        "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW30\n\
         END_ORGANIZATION_BLOCK\n\nSYSTEM_BLOCK\n  PASSWORD = \"{PASSWORD}\"\n\
         END_SYSTEM_BLOCK\n"
    );
    let dir = common::image_dir(
        &format!("password-{tag}"),
        &common::image("password.lad", &source),
    );
    common::sim("CPU-EC20", Some(&dir))
}

/// `gutta-cc status` at `sim`, stdin not a terminal, GUTTA_PASSWORD as given.
fn status(sim: &Sim, env: Option<&str>, extra: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_gutta-cc"));
    command
        .args(["status", "--tcp", &sim.1])
        .args(extra)
        .stdin(Stdio::null())
        .env_remove(PASSWORD_ENV);
    if let Some(value) = env {
        command.env(PASSWORD_ENV, value);
    }
    command.output().expect("gutta-cc runs")
}

fn logged_in(o: &Output) -> bool {
    o.status.success() && String::from_utf8_lossy(&o.stdout).starts_with("CPU-EC20: RUN")
}

#[test]
fn gutta_password_and_the_flag_log_in() {
    let sim = sim("sources");
    let o = status(&sim, Some(PASSWORD), &[]);
    assert!(logged_in(&o), "{}", stderr(&o));
    assert_eq!(stderr(&o), "", "GUTTA_PASSWORD needs no warning");
    // --password still works, with a warning that others can see it.
    let o = status(&sim, None, &["--password", PASSWORD]);
    assert!(logged_in(&o), "{}", stderr(&o));
    assert!(stderr(&o).contains("--password is visible to other users"));
    // The flag comes before the environment.
    let o = status(&sim, Some("not-it"), &["--password", PASSWORD]);
    assert!(logged_in(&o), "{}", stderr(&o));
}

#[test]
fn no_password_and_no_terminal_names_both_ways_to_give_one() {
    let sim = sim("none");
    // An empty GUTTA_PASSWORD is unset: the factory password is tried, and refused.
    for env in [None, Some("")] {
        let o = status(&sim, env, &[]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let text = stderr(&o);
        assert!(
            text.contains("set GUTTA_PASSWORD, or pass --password"),
            "{text}"
        );
        assert!(!text.contains("locked"), "{text}");
    }
}

#[test]
fn wrong_passwords_are_refused_then_the_lockout_says_so() {
    let sim = sim("lockout");
    // Two wrong passwords are free, the third locks ATTACH for 1 s: all three are
    // "refused", with the policy.
    for _ in 0..3 {
        let o = status(&sim, Some("wrong"), &[]);
        assert_eq!(o.status.code(), Some(2));
        assert!(stderr(&o).contains(REFUSED), "{}", stderr(&o));
        assert!(stderr(&o).contains("from the third wrong password"));
    }
    // Within that second even the right password meets the lockout, said as such.
    let o = status(&sim, Some(PASSWORD), &[]);
    assert_eq!(o.status.code(), Some(2));
    let text = stderr(&o);
    assert!(text.contains(LOCKED), "{text}");
    assert!(!text.contains("wrong password?"), "{text}");
    assert!(!text.contains(REFUSED), "{text}");
    // After it, the right password logs in (and resets the count).
    std::thread::sleep(Duration::from_millis(1100));
    let o = status(&sim, Some(PASSWORD), &[]);
    assert!(logged_in(&o), "{}", stderr(&o));
}

#[test]
fn a_terminal_gets_a_prompt_that_does_not_echo() {
    if !common::have("tmux") {
        return;
    }
    let sim = sim("prompt");
    let cc = PathBuf::from(env!("CARGO_BIN_EXE_gutta-cc"));
    let tmux = common::Tmux::new("gutta-password");
    let shell = format!(
        "env -u {PASSWORD_ENV} {} status --tcp {}; echo exit=$?; sleep 60",
        cc.display(),
        sim.1
    );
    tmux.run(&[
        "new-session",
        "-d",
        "-s",
        "pw",
        "-x",
        "160",
        "-y",
        "20",
        &shell,
    ]);
    let prompt = format!("Password for PLC at {}: ", sim.1);
    let screen = tmux.screen_when("pw", |s| s.contains(prompt.trim_end()));
    assert!(screen.contains(prompt.trim_end()), "{screen}");
    tmux.run(&["send-keys", "-t", "pw", "-l", PASSWORD]);
    tmux.run(&["send-keys", "-t", "pw", "Enter"]);
    let screen = tmux.screen_when("pw", |s| s.contains("exit="));
    assert!(screen.contains("exit=0"), "{screen}");
    assert!(screen.contains("CPU-EC20: RUN"), "{screen}");
    assert!(
        !screen.contains(PASSWORD),
        "the password was echoed:\n{screen}"
    );
}
