//! A timer preset as the time it stands for (docs/ladder.md, "Elements"; the language
//! server's hover and inlay hints): `PT 100` on a 100 ms timer is `10.0 s`. One home for
//! the wording, so the drawing, the editor and the test reports say it the same way.

/// `preset` units of `resolution_ms` as a duration: below one second in milliseconds
/// (`50 ms`), else in seconds with as many decimals as the resolution has below a second
/// (`10.0 s` at 100 ms, `1.25 s` at 10 ms, `3 s` at 1000 ms), from one minute on with the
/// minutes first (`2 min 3.5 s`). `None` for a negative preset or a zero resolution.
pub fn timer_duration(resolution_ms: u32, preset: i64) -> Option<String> {
    if preset < 0 || resolution_ms == 0 {
        return None;
    }
    let total_ms = preset.checked_mul(i64::from(resolution_ms))?;
    if total_ms < 1000 {
        return Some(format!("{total_ms} ms"));
    }
    let decimals = match resolution_ms % 1000 {
        0 => 0,
        r if r % 100 == 0 => 1,
        r if r % 10 == 0 => 2,
        _ => 3,
    };
    let minutes = total_ms / 60_000;
    let rest_ms = total_ms % 60_000;
    let seconds = seconds_text(rest_ms, decimals);
    Some(if minutes == 0 {
        format!("{seconds} s")
    } else {
        format!("{minutes} min {seconds} s")
    })
}

fn seconds_text(ms: i64, decimals: usize) -> String {
    let whole = ms / 1000;
    let fraction = ms % 1000;
    match decimals {
        0 => format!("{whole}"),
        1 => format!("{whole}.{}", fraction / 100),
        2 => format!("{whole}.{:02}", fraction / 10),
        _ => format!("{whole}.{fraction:03}"),
    }
}

#[cfg(test)]
mod tests {
    use super::timer_duration;

    #[test]
    fn durations_read_as_an_engineer_says_them() {
        let cases = [
            (100, 100, "10.0 s"),
            (100, 5, "500 ms"),
            (10, 125, "1.25 s"),
            (1, 1500, "1.500 s"),
            (1000, 3, "3 s"),
            (100, 1235, "2 min 3.5 s"),
            (100, 600, "1 min 0.0 s"),
            (10, 0, "0 ms"),
            (100, 32767, "54 min 36.7 s"),
        ];
        for (resolution, preset, text) in cases {
            assert_eq!(
                timer_duration(resolution, preset).as_deref(),
                Some(text),
                "{preset} x {resolution} ms"
            );
        }
        assert_eq!(timer_duration(100, -1), None);
        assert_eq!(timer_duration(0, 10), None);
    }
}
