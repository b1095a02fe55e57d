//! The edit operations as data: `Edit`, one variant per operation of docs/ladder.md
//! ("Editing the model"), with its JSON form (`{"op": "insert_contact", "at": PATH,
//! ...}`) as the studio sends it. Elements and networks inside an edit are read by the
//! model's own reader (`json::read`), so they take exactly the model's JSON. What an
//! edit does is `mod.rs`'s; this file only says what one is.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::path::{ElementPath, NetworkPath};
use crate::json::{
    read_element as read_json_element, read_network, Element, ModelError, ModelErrorCode as Code,
    NetworkJson,
};

/// Where an inserted element goes, relative to the selection (`at` and the `count`
/// elements of its series from it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Place {
    /// In series, before the selection's first element.
    Before,
    /// In series, after the selection's last element.
    After,
    /// In parallel around the selection: the selection becomes the upper branch, the new
    /// element the lower one (beside an output: a parallel output).
    Parallel,
}

/// One edit of a model. Element paths are `ElementPath`s (`blocks[0].networks[1].rung.
/// series[0]`); a selection is `at` and the `count` consecutive elements of its
/// `series` from it (1, the default: `at` alone, which may be any element).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case", deny_unknown_fields)]
pub enum Edit {
    /// A contact (`LD`, `LDN`, `LDW>=`, `EU`, `NOT`...) before, after or in parallel
    /// around the selection.
    InsertContact {
        at: ElementPath,
        #[serde(default = "one", skip_serializing_if = "is_one")]
        count: usize,
        place: Place,
        contact: String,
        #[serde(default)]
        operands: Vec<String>,
    },
    /// A coil (`=`, `S`, `R`, `=I`...): `after` the last element of a rung that ends in a
    /// box with a power output, or `parallel` beside an output.
    InsertCoil {
        at: ElementPath,
        #[serde(default = "one", skip_serializing_if = "is_one")]
        count: usize,
        place: Place,
        coil: String,
        #[serde(default)]
        operands: Vec<String>,
    },
    /// A box (`TON`, `MOVW`, `CTU`...) with its operands in STL order and its power
    /// inputs after the first, given as the model gives them (none are made up).
    InsertBox {
        at: ElementPath,
        #[serde(default = "one", skip_serializing_if = "is_one")]
        count: usize,
        place: Place,
        #[serde(rename = "box")]
        mnemonic: String,
        #[serde(default)]
        operands: Vec<String>,
        #[serde(default, with = "elements")]
        inputs: Vec<Element>,
    },
    /// The selection becomes the upper branch of a `parallel` whose lower branch is
    /// `branch` (a contact or a path of them; beside outputs, an output branch).
    WrapParallel {
        at: ElementPath,
        #[serde(default = "one", skip_serializing_if = "is_one")]
        count: usize,
        #[serde(with = "element")]
        branch: Element,
    },
    /// The selection is deleted and the wire closes.
    Delete {
        at: ElementPath,
        #[serde(default = "one", skip_serializing_if = "is_one")]
        count: usize,
    },
    /// A contact's, coil's or box's operands, all of them, in STL order.
    SetOperands {
        at: ElementPath,
        operands: Vec<String>,
    },
    /// A contact's, coil's or box's mnemonic (`LD` <-> `LDN`, `TON` -> `TOF`, `=` ->
    /// `S`); its operands (and a box's inputs) stay unless given.
    SetMnemonic {
        at: ElementPath,
        mnemonic: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        operands: Option<Vec<String>>,
        #[serde(
            default,
            skip_serializing_if = "Option::is_none",
            with = "some_elements"
        )]
        inputs: Option<Vec<Element>>,
    },
    /// `network` (the model's JSON of one network) at position `at` (the block's number
    /// of networks appends it).
    InsertNetwork {
        at: NetworkPath,
        #[serde(with = "network")]
        network: NetworkJson,
    },
    DeleteNetwork {
        at: NetworkPath,
    },
    /// The network at `at` moved to position `to` of its block (counted after it is
    /// taken out).
    MoveNetwork {
        at: NetworkPath,
        to: usize,
    },
    /// A copy of the network right after it.
    DuplicateNetwork {
        at: NetworkPath,
    },
    SetNetworkTitle {
        at: NetworkPath,
        title: String,
    },
    /// The comment lines, joined by newlines (`""`: none).
    SetNetworkComment {
        at: NetworkPath,
        comment: String,
    },
    /// A block's `TITLE=` (`null`: none); `block` is its place in `blocks`.
    SetBlockTitle {
        block: usize,
        title: Option<String>,
    },
}

impl Edit {
    /// The edit in `text` (its JSON form); L0018 when it is not one.
    pub fn from_json(text: &str) -> Result<Edit, ModelError> {
        serde_json::from_str(text).map_err(|e| {
            ModelError::new(Code::NotAnEdit, "", format!("not an edit operation: {e}"))
        })
    }

    /// The edit's JSON form, on one line.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }
}

fn one() -> usize {
    1
}

fn is_one(n: &usize) -> bool {
    *n == 1
}

/// An element of an edit, read as the model reads one (its L code in serde's message).
fn read_element(value: &serde_json::Value, path: &str) -> Result<Element, String> {
    read_json_element(value, path).map_err(|e| e.to_string())
}

mod element {
    use super::*;

    pub fn serialize<S: Serializer>(e: &Element, s: S) -> Result<S::Ok, S::Error> {
        e.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Element, D::Error> {
        let value = serde_json::Value::deserialize(d)?;
        read_element(&value, "branch").map_err(serde::de::Error::custom)
    }
}

mod elements {
    use super::*;

    pub fn serialize<S: Serializer>(e: &[Element], s: S) -> Result<S::Ok, S::Error> {
        e.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Element>, D::Error> {
        let values = Vec::<serde_json::Value>::deserialize(d)?;
        values
            .iter()
            .enumerate()
            .map(|(i, v)| read_element(v, &format!("inputs[{i}]")))
            .collect::<Result<_, _>>()
            .map_err(serde::de::Error::custom)
    }
}

mod some_elements {
    use super::*;

    pub fn serialize<S: Serializer>(e: &Option<Vec<Element>>, s: S) -> Result<S::Ok, S::Error> {
        e.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<Element>>, D::Error> {
        super::elements::deserialize(d).map(Some)
    }
}

mod network {
    use super::*;

    pub fn serialize<S: Serializer>(n: &NetworkJson, s: S) -> Result<S::Ok, S::Error> {
        n.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<NetworkJson, D::Error> {
        let value = serde_json::Value::deserialize(d)?;
        read_network(&value, "network").map_err(|e| serde::de::Error::custom(e.to_string()))
    }
}
