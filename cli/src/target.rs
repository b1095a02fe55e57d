//! The `--plc`/`--target` flags, declared once for gutta-cc, gutta-vm and gutta-sim, and
//! the target they choose together with a project, an image or a PLC, loaded, with the
//! load errors the tools print. Which input wins is `gutta_catalog::choose_target`'s
//! rule; nothing here decides it again.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gutta_catalog::{
    choose_target, ChosenTarget, OwnName, Target, TargetInputs, TargetOrigin, TargetSpec,
};
use gutta_compiler::ExplicitTarget;

use crate::fatal::Fatal;

/// `--plc NAME` / `--target DIR`, and the project's `[program] plc`/`target` when the
/// command runs in a project. A tool whose `--plc` means something narrower says so
/// with `#[command(mut_arg("plc", ...))]`.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct TargetArgs {
    /// PLC type from the stdlib (overrides PLC_TYPE in the file).
    #[arg(long, global = true, value_name = "NAME", value_parser = crate::flags::PlcName, hide_possible_values = true)]
    pub plc: Option<String>,
    /// A target folder holding PlcType.xml, ManagerVar.xml and ManagerFun.xml.
    #[arg(long, global = true, value_name = "DIR", conflicts_with = "plc")]
    pub target: Option<PathBuf>,
    /// The project's `[program] plc`/`target`, when the command uses a project (it is no
    /// flag: gutta-cc fills it from gutta.toml).
    #[arg(skip)]
    pub project: Option<TargetSpec>,
}

impl TargetArgs {
    /// The flags and the project as the resolver's inputs.
    pub fn inputs(&self) -> TargetInputs<'_> {
        TargetInputs {
            plc_flag: self.plc.as_deref(),
            target_flag: self.target.as_deref(),
            project: self.project.as_ref(),
            ..TargetInputs::default()
        }
    }

    /// The target the flags or the project name, loaded; `None` when neither names one
    /// (the program's `PLC_TYPE`, else the default, decides in the compiler).
    pub fn explicit(&self) -> Result<Option<ExplicitTarget>, Fatal> {
        explicit(&self.inputs())
    }

    /// The target of an image directory: the flags or the project, else the PLC type
    /// the image records.
    pub fn for_image(&self, plc: &str, dir: &Path) -> Result<Arc<Target>, Fatal> {
        load(&choose_target(&TargetInputs {
            own: Some(OwnName::Image { plc, dir }),
            ..self.inputs()
        }))
    }

    /// An image directory, read, and its target ([`TargetArgs::for_image`]).
    pub fn read_image(&self, dir: &Path) -> Result<(gutta_format::Image, Arc<Target>), Fatal> {
        let image = gutta_io::read_image_dir(dir).map_err(Fatal::io)?;
        let target = self.for_image(&image.plc_type, dir)?;
        Ok((image, target))
    }

    /// The target of a PLC: the flags or the project, else the PLC's own name, which
    /// `ask` fetches only then.
    pub fn for_plc(
        &self,
        ask: impl FnOnce() -> Result<String, Fatal>,
    ) -> Result<Arc<Target>, Fatal> {
        let chosen = match choose_target(&self.inputs()).named() {
            Some(chosen) => chosen,
            None => {
                let name = ask()?;
                choose_target(&TargetInputs {
                    own: Some(OwnName::Plc(&name)),
                    ..self.inputs()
                })
            }
        };
        load(&chosen)
    }
}

/// The target `inputs` name, loaded, as the compiler's explicit target; `None` when
/// none names one.
pub fn explicit(inputs: &TargetInputs<'_>) -> Result<Option<ExplicitTarget>, Fatal> {
    choose_target(inputs)
        .named()
        .map(|chosen| load_explicit(&chosen))
        .transpose()
}

/// The chosen target, loaded, as the compiler's explicit target (its origin for W0204).
pub fn load_explicit(chosen: &ChosenTarget) -> Result<ExplicitTarget, Fatal> {
    Ok(ExplicitTarget {
        target: load(chosen)?,
        origin: chosen.origin.to_string(),
    })
}

/// The chosen target, loaded; a failure is a target error whose text says where the
/// name came from when the user did not type it (an image, a PLC).
pub fn load(chosen: &ChosenTarget) -> Result<Arc<Target>, Fatal> {
    gutta_io::load_target(&chosen.spec).map_err(|e| {
        let name = match &chosen.spec {
            TargetSpec::Stdlib(name) => name.as_str(),
            TargetSpec::Folder(_) => "",
        };
        Fatal::target(match &chosen.origin {
            TargetOrigin::Image(_) => {
                format!("the image is for {name}: {e} (pass --target DIR for a vendor PLC type)")
            }
            TargetOrigin::Plc(_) => {
                format!("the PLC is a {name}: {e} (pass --target DIR for a vendor PLC type)")
            }
            _ => e,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flags_win_over_an_image_and_a_plc_which_is_not_asked() {
        let flags = TargetArgs {
            plc: Some("CPU-EC20".into()),
            ..TargetArgs::default()
        };
        let target = flags
            .for_image("NOPE", Path::new("image"))
            .expect("--plc wins");
        assert_eq!(target.name(), "CPU-EC20");
        let target = flags
            .for_plc(|| panic!("the PLC is asked only when nothing names a type"))
            .expect("--plc wins");
        assert_eq!(target.name(), "CPU-EC20");
        let explicit = flags.explicit().expect("loads").expect("named");
        assert_eq!(explicit.origin, "--plc CPU-EC20");
        assert!(TargetArgs::default().explicit().expect("none").is_none());
    }

    #[test]
    fn a_type_the_user_did_not_type_says_where_it_came_from() {
        let none = TargetArgs::default();
        let e = none
            .for_image("NOPE", Path::new("image"))
            .expect_err("unknown");
        assert!(
            e.message.starts_with("the image is for NOPE: "),
            "{}",
            e.message
        );
        assert!(e
            .message
            .ends_with("(pass --target DIR for a vendor PLC type)"));
        let e = none.for_plc(|| Ok("NOPE".into())).expect_err("unknown");
        assert!(
            e.message.starts_with("the PLC is a NOPE: "),
            "{}",
            e.message
        );
        let project = TargetArgs {
            project: Some(TargetSpec::Stdlib("CPU-EC20".into())),
            ..TargetArgs::default()
        };
        let explicit = project.explicit().expect("loads").expect("named");
        assert_eq!(explicit.origin, TargetOrigin::ProjectPlc.to_string());
    }
}
