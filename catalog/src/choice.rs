//! Which PLC type applies, decided once for every tool and the language server: the
//! command line (`--plc`/`--target`), else a test file's `PLC_TYPE`, else the project's
//! `[program] plc`/`target`, else what the input itself names (the program's `PLC_TYPE`,
//! an image's PLC type, the PLC's answer), else the stdlib default. [`TargetOrigin`]'s
//! `Display` is the wording messages use for where the choice came from (W0204, the
//! load errors). Plain data in and out: it loads nothing (that is `stdlib::shared`'s and
//! `gutta_io::load_target_dir`'s) and reads no file.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::stdlib;

/// A PLC type to load: a stdlib name, or a target folder (PlcType.xml, ManagerVar.xml,
/// ManagerFun.xml).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TargetSpec {
    Stdlib(String),
    Folder(PathBuf),
}

/// What an input names itself, the last layer before the default.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OwnName<'a> {
    /// The program's `PLC_TYPE` line.
    Source(&'a str),
    /// An image directory's manifest: its PLC type, and the directory.
    Image { plc: &'a str, dir: &'a Path },
    /// The PLC's answer to GET_PLC_NAME.
    Plc(&'a str),
}

/// Everything that may name a PLC type, each `None` when it does not.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TargetInputs<'a> {
    /// `--plc NAME`.
    pub plc_flag: Option<&'a str>,
    /// `--target DIR`.
    pub target_flag: Option<&'a Path>,
    /// A test file's `PLC_TYPE` (for the program the test file runs).
    pub test_file: Option<&'a str>,
    /// The project's `[program] plc` or `[program] target`.
    pub project: Option<&'a TargetSpec>,
    /// What the input names itself.
    pub own: Option<OwnName<'a>>,
}

/// Where the chosen PLC type came from. `Display` gives the wording of messages:
/// `--plc CPU-EC20`, `[program] plc in gutta.toml`, `the image in image/`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TargetOrigin {
    PlcFlag(String),
    TargetFlag(PathBuf),
    /// `PLC_TYPE NAME` in a test file.
    TestFile(String),
    /// `[program] plc` in gutta.toml.
    ProjectPlc,
    /// `[program] target` in gutta.toml.
    ProjectFolder,
    /// The program's own `PLC_TYPE NAME`.
    Source(String),
    /// The PLC type an image directory records.
    Image(PathBuf),
    /// The PLC's own answer.
    Plc(String),
    /// Nothing named one.
    Default,
}

impl TargetOrigin {
    /// The project key it came from (`[program] plc`), for a project's own messages.
    pub fn project_key(&self) -> Option<&'static str> {
        match self {
            TargetOrigin::ProjectPlc => Some("[program] plc"),
            TargetOrigin::ProjectFolder => Some("[program] target"),
            _ => None,
        }
    }

    /// Whether the command line chose it (`--plc`, `--target`).
    pub fn is_command_line(&self) -> bool {
        matches!(self, TargetOrigin::PlcFlag(_) | TargetOrigin::TargetFlag(_))
    }

    /// Whether something named the PLC type (anything but the default).
    pub fn is_named(&self) -> bool {
        *self != TargetOrigin::Default
    }
}

impl fmt::Display for TargetOrigin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(key) = self.project_key() {
            return write!(f, "{key} in gutta.toml");
        }
        match self {
            TargetOrigin::PlcFlag(name) => write!(f, "--plc {name}"),
            TargetOrigin::TargetFlag(dir) => write!(f, "--target {}", dir.display()),
            TargetOrigin::TestFile(name) => write!(f, "PLC_TYPE {name} in the test file"),
            TargetOrigin::Source(name) => write!(f, "PLC_TYPE {name} in the program"),
            TargetOrigin::Image(dir) => write!(f, "the image in {}", dir.display()),
            TargetOrigin::Plc(name) => write!(f, "the PLC's type {name}"),
            TargetOrigin::Default => write!(f, "the stdlib default {}", stdlib::DEFAULT),
            TargetOrigin::ProjectPlc | TargetOrigin::ProjectFolder => Ok(()),
        }
    }
}

/// The PLC type chosen and where it came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChosenTarget {
    pub spec: TargetSpec,
    pub origin: TargetOrigin,
}

impl ChosenTarget {
    /// The chosen target when something named it; `None` for the default.
    pub fn named(self) -> Option<ChosenTarget> {
        self.origin.is_named().then_some(self)
    }
}

/// The rule: the first input that names a PLC type wins, in the order of
/// [`TargetInputs`]' fields; when none does, the stdlib default.
pub fn choose_target(inputs: &TargetInputs<'_>) -> ChosenTarget {
    let stdlib = |name: &str, origin| ChosenTarget {
        spec: TargetSpec::Stdlib(name.to_string()),
        origin,
    };
    if let Some(name) = inputs.plc_flag {
        return stdlib(name, TargetOrigin::PlcFlag(name.to_string()));
    }
    if let Some(dir) = inputs.target_flag {
        return ChosenTarget {
            spec: TargetSpec::Folder(dir.to_path_buf()),
            origin: TargetOrigin::TargetFlag(dir.to_path_buf()),
        };
    }
    if let Some(name) = inputs.test_file {
        return stdlib(name, TargetOrigin::TestFile(name.to_string()));
    }
    if let Some(spec) = inputs.project {
        let origin = match spec {
            TargetSpec::Stdlib(_) => TargetOrigin::ProjectPlc,
            TargetSpec::Folder(_) => TargetOrigin::ProjectFolder,
        };
        return ChosenTarget {
            spec: spec.clone(),
            origin,
        };
    }
    match inputs.own {
        Some(OwnName::Source(name)) => stdlib(name, TargetOrigin::Source(name.to_string())),
        Some(OwnName::Image { plc, dir }) => stdlib(plc, TargetOrigin::Image(dir.to_path_buf())),
        Some(OwnName::Plc(name)) => stdlib(name, TargetOrigin::Plc(name.to_string())),
        None => stdlib(stdlib::DEFAULT, TargetOrigin::Default),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn origin(inputs: TargetInputs<'_>) -> String {
        choose_target(&inputs).origin.to_string()
    }

    #[test]
    fn each_input_wins_over_the_ones_after_it() {
        let project = TargetSpec::Stdlib("EC30-EKSTM32".into());
        let all = TargetInputs {
            plc_flag: Some("CPU-EC20"),
            target_flag: None,
            test_file: Some("EC10-EKSTM32"),
            project: Some(&project),
            own: Some(OwnName::Source("CPU-EC20")),
        };
        assert_eq!(origin(all), "--plc CPU-EC20");
        let no_flags = TargetInputs {
            plc_flag: None,
            ..all
        };
        assert_eq!(origin(no_flags), "PLC_TYPE EC10-EKSTM32 in the test file");
        let project_next = TargetInputs {
            test_file: None,
            ..no_flags
        };
        let chosen = choose_target(&project_next);
        assert_eq!(chosen.spec, project);
        assert_eq!(chosen.origin.to_string(), "[program] plc in gutta.toml");
        let own = TargetInputs {
            project: None,
            ..project_next
        };
        assert_eq!(origin(own), "PLC_TYPE CPU-EC20 in the program");
        let none = choose_target(&TargetInputs::default());
        assert_eq!(none.spec, TargetSpec::Stdlib(stdlib::DEFAULT.into()));
        assert_eq!(none.named(), None);
    }

    #[test]
    fn folders_keep_their_path_and_wording() {
        let dir = Path::new("vendor/EC99");
        let chosen = choose_target(&TargetInputs {
            target_flag: Some(dir),
            ..TargetInputs::default()
        });
        assert_eq!(chosen.spec, TargetSpec::Folder(dir.into()));
        assert_eq!(chosen.origin.to_string(), "--target vendor/EC99");
        let project = TargetSpec::Folder(dir.into());
        let chosen = choose_target(&TargetInputs {
            project: Some(&project),
            ..TargetInputs::default()
        });
        assert_eq!(chosen.origin.to_string(), "[program] target in gutta.toml");
        assert_eq!(chosen.origin.project_key(), Some("[program] target"));
    }

    #[test]
    fn an_image_or_a_plc_names_itself_below_the_command_line() {
        let dir = Path::new("image");
        let image = TargetInputs {
            own: Some(OwnName::Image {
                plc: "EC30-EKSTM32",
                dir,
            }),
            ..TargetInputs::default()
        };
        let chosen = choose_target(&image);
        assert_eq!(chosen.spec, TargetSpec::Stdlib("EC30-EKSTM32".into()));
        assert_eq!(chosen.origin.to_string(), "the image in image");
        let flagged = TargetInputs {
            plc_flag: Some("CPU-EC20"),
            ..image
        };
        assert_eq!(
            choose_target(&flagged).spec,
            TargetSpec::Stdlib("CPU-EC20".into())
        );
        let plc = choose_target(&TargetInputs {
            own: Some(OwnName::Plc("CPU-EC20")),
            ..TargetInputs::default()
        });
        assert_eq!(plc.origin, TargetOrigin::Plc("CPU-EC20".into()));
    }
}
