//! Timer resolutions (docs/microwin.md, "Timer resolutions"): on an S7-200 a timer's
//! number fixes its resolution; where the target's differs, W0207, or with
//! `--scale-timer-presets` the constant presets are scaled to keep the S7-200 timing.

use std::collections::HashSet;

use gutta_catalog::s7200_timers::{s7200_timer_resolution, scale_preset, S7200TimerFamily};

use super::TimerBitPass;
use crate::check::{CheckedOperand, CheckedUnit, ConstValue, TimerBox};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;

impl TimerBitPass<'_> {
    /// W0207 for every timer number whose S7-200 resolution differs from the target's,
    /// once per number; with `--scale-timer-presets` its constant presets are scaled
    /// instead (W0207 only where rounding changes the time, or the preset is in memory).
    /// Returns the spans of the presets it scaled.
    pub(super) fn timer_resolutions(
        &mut self,
        checked: &mut [CheckedUnit],
        boxes: &[TimerBox],
    ) -> HashSet<Span> {
        let mut scaled_presets = HashSet::new();
        let mut warned: HashSet<u32> = HashSet::new();
        for b in boxes {
            let ins = &checked[b.unit].networks[b.network].instructions[b.index];
            let spec = self.target.instructions.get(ins.id);
            let Some(family) = spec.kind.and_then(S7200TimerFamily::of_kind) else {
                continue;
            };
            let Some(CheckedOperand::Memory { address, .. }) = ins.operands.first() else {
                continue;
            };
            let number = address.offset / 2;
            let (Some(s7), Some(here)) = (
                s7200_timer_resolution(family, number),
                self.target.memory.timer_resolution(number),
            ) else {
                continue;
            };
            if s7 == here {
                continue;
            }
            let preset = ins.operands.get(1).copied();
            let constant = match preset {
                Some(CheckedOperand::Constant {
                    value: ConstValue::Integer(v),
                    ..
                }) => Some(v),
                _ => None,
            };
            let timer = format!("T{number}");
            let target = self.target.name().to_string();
            let both = format!(
                "`{timer}` counts {s7} ms on an S7-200 ({}) and {here} ms on {target}",
                family.describe()
            );
            if !self.options.scale_timer_presets {
                if !warned.insert(number) {
                    continue;
                }
                let effect = match constant {
                    Some(v) => format!(
                        "its preset {v} means {} on an S7-200 and {} here",
                        duration(v, s7),
                        duration(v, here)
                    ),
                    None => format!(
                        "its preset `{}` is in units of {here} ms here, not {s7} ms",
                        self.slice(b.preset)
                    ),
                };
                let help = match constant.and_then(|v| scale_preset(v, s7, here)) {
                    Some(scaled) => format!(
                        "--scale-timer-presets keeps the S7-200 timing ({} becomes {scaled}), or use a timer number with {s7} ms here",
                        constant.unwrap_or_default()
                    ),
                    None => format!("use a timer number that counts {s7} ms on {target}, or rewrite the preset"),
                };
                self.report(
                    Diagnostic::new(Code::TimerResolution, b.preset, format!("{both}: {effect}"))
                        .help(help),
                );
                continue;
            }
            let Some(v) = constant else {
                if warned.insert(number) {
                    self.report(
                        Diagnostic::new(
                            Code::TimerResolution,
                            b.preset,
                            format!(
                                "{both}: the preset `{}` is in memory, so --scale-timer-presets cannot scale it",
                                self.slice(b.preset)
                            ),
                        )
                        .help(format!("store the preset in units of {here} ms")),
                    );
                }
                continue;
            };
            let Some(scaled) = scale_preset(v, s7, here) else {
                self.report(
                    Diagnostic::new(
                        Code::ConstantOutOfRange,
                        b.preset,
                        format!(
                            "{both}: the preset {v} ({}) does not fit a preset in {here} ms units (at most 32767)",
                            duration(v, s7)
                        ),
                    )
                    .help(format!("use a timer number that counts {s7} ms on {target}")),
                );
                continue;
            };
            if scaled * i64::from(here) != v * i64::from(s7) && warned.insert(number) {
                self.report(Diagnostic::new(
                    Code::TimerResolution,
                    b.preset,
                    format!(
                        "{both}: the preset {v} ({}) is scaled to {scaled} ({}), the nearest it can count",
                        duration(v, s7),
                        duration(scaled, here)
                    ),
                ));
            }
            if let Some(CheckedOperand::Constant { value, .. }) =
                checked[b.unit].networks[b.network].instructions[b.index]
                    .operands
                    .get_mut(1)
            {
                *value = ConstValue::Integer(scaled);
                scaled_presets.insert(b.preset);
            }
        }
        scaled_presets
    }
}

/// `units` of `ms` milliseconds, for messages: `5 s`, `0.5 s`, `40 ms`.
fn duration(units: i64, ms: u32) -> String {
    let total = units * i64::from(ms);
    if total.abs() < 1000 {
        format!("{total} ms")
    } else if total % 1000 == 0 {
        format!("{} s", total / 1000)
    } else {
        format!("{} s", total as f64 / 1000.0)
    }
}

#[cfg(test)]
mod tests {
    use super::duration;

    #[test]
    fn durations_read_naturally() {
        assert_eq!(duration(5, 100), "500 ms");
        assert_eq!(duration(50, 100), "5 s");
        assert_eq!(duration(15, 100), "1.5 s");
        assert_eq!(duration(4, 10), "40 ms");
    }
}
