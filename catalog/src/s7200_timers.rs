//! S7-200 timer numbers and their resolutions: on an S7-200 a timer's number fixes both
//! the instructions that may drive it and how long one unit of its preset lasts (CPU
//! 22x; the S7-200 SMART numbers its timers the same way). Plain data from the public
//! S7-200 system manual; the compiler compares it with the target's `<Timers>` rows
//! (docs/microwin.md, "Timer resolutions").

use crate::TimerCounterKind;

/// The S7-200's two timer families: their numbers' resolutions differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum S7200TimerFamily {
    /// `TON` and `TOF` share their numbers.
    OnOffDelay,
    /// `TONR`, the retentive on-delay timer.
    Retentive,
}

impl S7200TimerFamily {
    /// The family of a timer kind (`None` for a counter): what the S7-200 numbers a
    /// `TON`, `TOF` or `TONR` by. Read the kind from the catalog (`Instruction::kind`).
    pub fn of_kind(kind: TimerCounterKind) -> Option<S7200TimerFamily> {
        match kind {
            TimerCounterKind::OnDelay | TimerCounterKind::OffDelay => {
                Some(S7200TimerFamily::OnOffDelay)
            }
            TimerCounterKind::RetentiveOnDelay => Some(S7200TimerFamily::Retentive),
            TimerCounterKind::CountUp
            | TimerCounterKind::CountDown
            | TimerCounterKind::CountUpDown => None,
        }
    }

    /// How the family is named in messages.
    pub fn describe(self) -> &'static str {
        match self {
            S7200TimerFamily::OnOffDelay => "TON/TOF",
            S7200TimerFamily::Retentive => "TONR",
        }
    }
}

/// Timer numbers (inclusive ranges) and their resolution in milliseconds, per family.
const ON_OFF_DELAY: &[(u32, u32, u32)] = &[
    (32, 32, 1),
    (33, 36, 10),
    (37, 63, 100),
    (96, 96, 1),
    (97, 100, 10),
    (101, 255, 100),
];
const RETENTIVE: &[(u32, u32, u32)] = &[
    (0, 0, 1),
    (1, 4, 10),
    (5, 31, 100),
    (64, 64, 1),
    (65, 68, 10),
    (69, 95, 100),
];

/// The resolution in milliseconds of S7-200 timer `number` driven by an instruction of
/// `family`, or None where the S7-200 has no such timer (TON on T0, TONR on T37).
pub fn s7200_timer_resolution(family: S7200TimerFamily, number: u32) -> Option<u32> {
    let table = match family {
        S7200TimerFamily::OnOffDelay => ON_OFF_DELAY,
        S7200TimerFamily::Retentive => RETENTIVE,
    };
    table
        .iter()
        .find(|(first, last, _)| (*first..=*last).contains(&number))
        .map(|(_, _, ms)| *ms)
}

/// A preset of `preset` units of `from_ms` expressed in units of `to_ms`: rounded to the
/// nearest unit (halves away from zero), and at least 1 for a positive preset (0 would
/// be done at once). `None` when the result does not fit an INT preset (32767).
pub fn scale_preset(preset: i64, from_ms: u32, to_ms: u32) -> Option<i64> {
    if to_ms == 0 {
        return None;
    }
    let num = i128::from(preset) * i128::from(from_ms);
    let den = i128::from(to_ms);
    let rounded = if num >= 0 {
        (num + den / 2) / den
    } else {
        (num - den / 2) / den
    };
    let scaled = if preset > 0 { rounded.max(1) } else { rounded };
    i64::try_from(scaled)
        .ok()
        .filter(|v| (i64::from(i16::MIN)..=i64::from(i16::MAX)).contains(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolutions_follow_the_s7_200_table() {
        use S7200TimerFamily::*;
        assert_eq!(s7200_timer_resolution(OnOffDelay, 32), Some(1));
        assert_eq!(s7200_timer_resolution(OnOffDelay, 96), Some(1));
        assert_eq!(s7200_timer_resolution(OnOffDelay, 33), Some(10));
        assert_eq!(s7200_timer_resolution(OnOffDelay, 100), Some(10));
        assert_eq!(s7200_timer_resolution(OnOffDelay, 37), Some(100));
        assert_eq!(s7200_timer_resolution(OnOffDelay, 255), Some(100));
        assert_eq!(s7200_timer_resolution(OnOffDelay, 0), None);
        assert_eq!(s7200_timer_resolution(OnOffDelay, 64), None);
        assert_eq!(s7200_timer_resolution(Retentive, 0), Some(1));
        assert_eq!(s7200_timer_resolution(Retentive, 4), Some(10));
        assert_eq!(s7200_timer_resolution(Retentive, 31), Some(100));
        assert_eq!(s7200_timer_resolution(Retentive, 64), Some(1));
        assert_eq!(s7200_timer_resolution(Retentive, 68), Some(10));
        assert_eq!(s7200_timer_resolution(Retentive, 95), Some(100));
        assert_eq!(s7200_timer_resolution(Retentive, 37), None);
        // Every number 0..=255 belongs to exactly one family.
        for n in 0..=255 {
            let on = s7200_timer_resolution(OnOffDelay, n).is_some();
            let r = s7200_timer_resolution(Retentive, n).is_some();
            assert!(on ^ r, "T{n}");
        }
    }

    #[test]
    fn the_family_follows_the_catalogs_kind() {
        let set = crate::stdlib::default_target()
            .expect("stdlib")
            .instructions;
        for ins in &set.instructions {
            let by_kind = ins.kind.and_then(S7200TimerFamily::of_kind);
            let expected = match ins.mnemonic.as_str() {
                "TON" | "TOF" => Some(S7200TimerFamily::OnOffDelay),
                "TONR" => Some(S7200TimerFamily::Retentive),
                _ => None,
            };
            assert_eq!(by_kind, expected, "{}", ins.mnemonic);
        }
        assert_eq!(
            S7200TimerFamily::of_kind(TimerCounterKind::RetentiveOnDelay),
            Some(S7200TimerFamily::Retentive)
        );
    }

    #[test]
    fn presets_scale_to_the_nearest_unit() {
        // 50 x 10 ms = 500 ms = 5 x 100 ms.
        assert_eq!(scale_preset(50, 10, 100), Some(5));
        // 5 x 10 ms = 50 ms: half a 100 ms unit rounds up.
        assert_eq!(scale_preset(5, 10, 100), Some(1));
        // 4 x 10 ms = 40 ms rounds to 0, kept at 1.
        assert_eq!(scale_preset(4, 10, 100), Some(1));
        assert_eq!(scale_preset(14, 10, 100), Some(1));
        assert_eq!(scale_preset(15, 10, 100), Some(2));
        assert_eq!(scale_preset(30, 100, 10), Some(300));
        assert_eq!(scale_preset(0, 100, 10), Some(0));
        assert_eq!(scale_preset(-15, 10, 100), Some(-2));
        assert_eq!(scale_preset(400, 100, 1), None);
        assert_eq!(scale_preset(327, 100, 1), Some(32700));
    }
}
