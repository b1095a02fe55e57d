//! Where an edit applies, as typed paths whose text is the JSON path the L codes name
//! (`blocks[0].networks[2].rung.series[1]`, `...rung.series[2].inputs[0].series[0]`),
//! so an editor can send back the path of an error. Parsing and printing only: what is
//! at a path is `rung.rs`'s.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::json::{ModelError, ModelErrorCode as Code};

/// One step down from an element: into a `series`, a `parallel` or a box's `inputs`,
/// at an index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Step {
    Series(usize),
    Parallel(usize),
    Input(usize),
}

impl Step {
    /// The index inside the list the step goes into.
    pub fn index(self) -> usize {
        match self {
            Step::Series(i) | Step::Parallel(i) | Step::Input(i) => i,
        }
    }

    /// The same kind of step at index `i`.
    pub fn with_index(self, i: usize) -> Step {
        match self {
            Step::Series(_) => Step::Series(i),
            Step::Parallel(_) => Step::Parallel(i),
            Step::Input(_) => Step::Input(i),
        }
    }

    fn key(self) -> &'static str {
        match self {
            Step::Series(_) => "series",
            Step::Parallel(_) => "parallel",
            Step::Input(_) => "inputs",
        }
    }
}

/// A network: `blocks[B].networks[N]`, both places counted from 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NetworkPath {
    pub block: usize,
    pub network: usize,
}

/// An element of a network's rung: `blocks[B].networks[N].rung` and the steps down
/// from the rung's element (none: the rung's element itself).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ElementPath {
    pub block: usize,
    pub network: usize,
    pub steps: Vec<Step>,
}

impl ElementPath {
    /// The rung's element of network `network` of block `block`.
    pub fn rung(block: usize, network: usize) -> ElementPath {
        ElementPath {
            block,
            network,
            steps: Vec::new(),
        }
    }

    /// This path one step further down.
    pub fn then(&self, step: Step) -> ElementPath {
        let mut steps = self.steps.clone();
        steps.push(step);
        ElementPath { steps, ..*self }
    }

    /// The network the element is in.
    pub fn network_path(&self) -> NetworkPath {
        NetworkPath {
            block: self.block,
            network: self.network,
        }
    }
}

impl fmt::Display for NetworkPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "blocks[{}].networks[{}]", self.block, self.network)
    }
}

impl fmt::Display for ElementPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.rung", self.network_path())?;
        for step in &self.steps {
            write!(f, ".{}[{}]", step.key(), step.index())?;
        }
        Ok(())
    }
}

/// `text` is not a path of the kind wanted: L0014.
fn not_a_path(text: &str, want: &str) -> ModelError {
    ModelError::new(Code::NoSuchPath, text, format!("`{text}` is not {want}"))
}

/// `key[index]` at the start of `text`, and the rest after it.
fn indexed<'t>(text: &'t str, key: &str) -> Option<(usize, &'t str)> {
    let rest = text.strip_prefix(key)?.strip_prefix('[')?;
    let close = rest.find(']')?;
    let digits = &rest[..close];
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    Some((digits.parse().ok()?, &rest[close + 1..]))
}

/// A step's key in a path and the step it makes.
type StepKey = (&'static str, fn(usize) -> Step);

const STEP_KEYS: [StepKey; 3] = [
    ("series", Step::Series),
    ("parallel", Step::Parallel),
    ("inputs", Step::Input),
];

/// `blocks[B].networks[N]` at the start of `text`, and the rest.
fn network_prefix(text: &str) -> Option<(NetworkPath, &str)> {
    let (block, rest) = indexed(text, "blocks")?;
    let (network, rest) = indexed(rest.strip_prefix('.')?, "networks")?;
    Some((NetworkPath { block, network }, rest))
}

impl FromStr for NetworkPath {
    type Err = ModelError;

    fn from_str(text: &str) -> Result<NetworkPath, ModelError> {
        match network_prefix(text) {
            Some((path, "")) => Ok(path),
            _ => Err(not_a_path(
                text,
                "a network's path (`blocks[0].networks[2]`)",
            )),
        }
    }
}

impl FromStr for ElementPath {
    type Err = ModelError;

    fn from_str(text: &str) -> Result<ElementPath, ModelError> {
        let bad = || {
            not_a_path(
                text,
                "an element's path (`blocks[0].networks[2].rung.series[1]`)",
            )
        };
        let (net, rest) = network_prefix(text).ok_or_else(bad)?;
        let mut rest = rest.strip_prefix(".rung").ok_or_else(bad)?;
        let mut path = ElementPath::rung(net.block, net.network);
        while !rest.is_empty() {
            let after_dot = rest.strip_prefix('.').ok_or_else(bad)?;
            let (step, next) = STEP_KEYS
                .iter()
                .find_map(|(key, make)| indexed(after_dot, key).map(|(i, r)| (make(i), r)))
                .ok_or_else(bad)?;
            path.steps.push(step);
            rest = next;
        }
        Ok(path)
    }
}

macro_rules! serde_as_text {
    ($ty:ty) => {
        impl Serialize for $ty {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.collect_str(self)
            }
        }

        impl<'de> Deserialize<'de> for $ty {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<$ty, D::Error> {
                let text = String::deserialize(d)?;
                text.parse().map_err(serde::de::Error::custom)
            }
        }
    };
}

serde_as_text!(NetworkPath);
serde_as_text!(ElementPath);
