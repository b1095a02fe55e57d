//! JSON text into the model (`super::Model`), every failure an L code with the JSON
//! path of the part at fault: not JSON (L0001), a missing field or a wrong type
//! (L0002), another `format` (L0003), a later `version` (L0004). Fields beyond the
//! format's are ignored. The catalog's checks are `validate.rs`'s.

use serde_json::{Map, Value};

use super::codes::{ModelError, ModelErrorCode as Code};
use super::{BlockJson, Element, Model, NetworkBody, NetworkJson, SymbolJson, VarJson};

type Read<T> = Result<T, ModelError>;

/// The model in `text`, its shape checked; `validate` checks it against the catalog.
pub fn read_model(text: &[u8]) -> Read<Model> {
    let value: Value = serde_json::from_slice(text)
        .map_err(|e| ModelError::new(Code::NotJson, "", format!("not JSON: {e}")))?;
    let top = object(&value, "")?;
    let format = string(top, "", "format")?;
    if format != super::FORMAT {
        return Err(ModelError::new(
            Code::UnknownFormat,
            "format",
            format!("the format is `{format}`, not `{}`", super::FORMAT),
        ));
    }
    let version = match top.get("version") {
        Some(Value::Number(n)) => n.as_u64(),
        None => return Err(missing("", "version")),
        Some(_) => None,
    }
    .filter(|v| *v >= 1)
    .ok_or_else(|| wrong("version", "a version number (1)"))?;
    if version > super::VERSION {
        return Err(ModelError::new(
            Code::LaterVersion,
            "version",
            format!(
                "version {version} is later than this tool reads (version {})",
                super::VERSION
            ),
        ));
    }
    let symbols = match top.get("symbols") {
        None => Vec::new(),
        Some(v) => array(v, "symbols")?
            .iter()
            .enumerate()
            .map(|(i, s)| symbol(s, &format!("symbols[{i}]")))
            .collect::<Read<_>>()?,
    };
    let blocks = array(field(top, "", "blocks")?, "blocks")?
        .iter()
        .enumerate()
        .map(|(i, b)| block(b, &format!("blocks[{i}]")))
        .collect::<Read<_>>()?;
    Ok(Model {
        format: format.to_string(),
        version,
        plc: string(top, "", "plc")?.to_string(),
        symbols,
        blocks,
    })
}

fn symbol(v: &Value, path: &str) -> Read<SymbolJson> {
    let o = object(v, path)?;
    Ok(SymbolJson {
        name: string(o, path, "name")?.to_string(),
        address: string(o, path, "address")?.to_string(),
        data_type: optional_string(o, path, "type")?,
        comment: optional_string(o, path, "comment")?,
    })
}

fn block(v: &Value, path: &str) -> Read<BlockJson> {
    let o = object(v, path)?;
    let section = |key: &str| -> Read<Vec<VarJson>> {
        let Some(list) = o.get(key) else {
            return Ok(Vec::new());
        };
        let at = join(path, key);
        array(list, &at)?
            .iter()
            .enumerate()
            .map(|(i, v)| var(v, &format!("{at}[{i}]")))
            .collect()
    };
    let at = join(path, "networks");
    let networks = array(field(o, path, "networks")?, &at)?
        .iter()
        .enumerate()
        .map(|(i, n)| network(n, &format!("{at}[{i}]")))
        .collect::<Read<_>>()?;
    Ok(BlockJson {
        kind: string(o, path, "kind")?.to_string(),
        name: string(o, path, "name")?.to_string(),
        id: string(o, path, "id")?.to_string(),
        title: optional_string(o, path, "title")?,
        var_input: section("VAR_INPUT")?,
        var_in_out: section("VAR_IN_OUT")?,
        var_output: section("VAR_OUTPUT")?,
        var: section("VAR")?,
        networks,
    })
}

fn var(v: &Value, path: &str) -> Read<VarJson> {
    let o = object(v, path)?;
    Ok(VarJson {
        name: string(o, path, "name")?.to_string(),
        data_type: string(o, path, "type")?.to_string(),
        comment: optional_string(o, path, "comment")?,
    })
}

/// One network at `path` (also how an edit's new network is read).
pub(crate) fn network(v: &Value, path: &str) -> Read<NetworkJson> {
    let o = object(v, path)?;
    let number = match o.get("number") {
        None | Some(Value::Null) => None,
        Some(n) => Some(
            n.as_u64()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or_else(|| wrong(&join(path, "number"), "a network number"))?,
        ),
    };
    let body = match (o.get("rung"), o.get("stl")) {
        (Some(rung), None) => NetworkBody::Rung {
            rung: element(rung, &join(path, "rung"))?,
        },
        (None, Some(stl)) => NetworkBody::Stl {
            stl: strings(stl, &join(path, "stl"))?,
            reason: optional_string(o, path, "reason")?.unwrap_or_default(),
        },
        (Some(_), Some(_)) => {
            return Err(ModelError::new(
                Code::Shape,
                path,
                "a network has either `rung` or `stl`, not both",
            ))
        }
        (None, None) => {
            return Err(ModelError::new(
                Code::Shape,
                path,
                "a network has `rung` (one rung) or `stl` (its lines)",
            ))
        }
    };
    Ok(NetworkJson {
        number,
        title: optional_string(o, path, "title")?.unwrap_or_default(),
        comment: optional_string(o, path, "comment")?.unwrap_or_default(),
        body,
    })
}

/// The element keys, one of which an element object has.
const ELEMENT_KEYS: [&str; 5] = ["series", "parallel", "contact", "coil", "box"];

/// One element at `path` (also how an edit's new elements are read).
pub(crate) fn element(v: &Value, path: &str) -> Read<Element> {
    let o = object(v, path)?;
    let present: Vec<&str> = ELEMENT_KEYS
        .into_iter()
        .filter(|k| o.contains_key(*k))
        .collect();
    let [key] = present.as_slice() else {
        return Err(ModelError::new(
            Code::Shape,
            path,
            format!(
                "an element has exactly one of `series`, `parallel`, `contact`, `coil`, `box` (found {})",
                if present.is_empty() { "none".to_string() } else { present.join(", ") }
            ),
        ));
    };
    let elements = |key: &str| -> Read<Vec<Element>> {
        let at = join(path, key);
        match o.get(key) {
            None => Ok(Vec::new()),
            Some(list) => array(list, &at)?
                .iter()
                .enumerate()
                .map(|(i, e)| element(e, &format!("{at}[{i}]")))
                .collect(),
        }
    };
    let operands = || -> Read<Vec<String>> {
        o.get("operands")
            .map_or(Ok(Vec::new()), |v| strings(v, &join(path, "operands")))
    };
    Ok(match *key {
        "series" => Element::Series {
            series: elements("series")?,
        },
        "parallel" => Element::Parallel {
            parallel: elements("parallel")?,
        },
        "contact" => Element::Contact {
            contact: string(o, path, "contact")?.to_string(),
            operands: operands()?,
        },
        "coil" => Element::Coil {
            coil: string(o, path, "coil")?.to_string(),
            operands: operands()?,
        },
        _ => Element::Box {
            mnemonic: string(o, path, "box")?.to_string(),
            operands: operands()?,
            inputs: elements("inputs")?,
        },
    })
}

/// `path.key`, or `key` at the top.
fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

fn missing(path: &str, key: &str) -> ModelError {
    ModelError::new(Code::Shape, &join(path, key), format!("`{key}` is missing"))
}

fn wrong(path: &str, want: &str) -> ModelError {
    ModelError::new(Code::Shape, path, format!("expected {want}"))
}

fn object<'v>(v: &'v Value, path: &str) -> Read<&'v Map<String, Value>> {
    v.as_object().ok_or_else(|| wrong(path, "an object"))
}

fn array<'v>(v: &'v Value, path: &str) -> Read<&'v Vec<Value>> {
    v.as_array().ok_or_else(|| wrong(path, "an array"))
}

fn field<'v>(o: &'v Map<String, Value>, path: &str, key: &str) -> Read<&'v Value> {
    o.get(key).ok_or_else(|| missing(path, key))
}

fn string<'v>(o: &'v Map<String, Value>, path: &str, key: &str) -> Read<&'v str> {
    field(o, path, key)?
        .as_str()
        .ok_or_else(|| wrong(&join(path, key), "a string"))
}

fn optional_string(o: &Map<String, Value>, path: &str, key: &str) -> Read<Option<String>> {
    match o.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s.clone())),
        Some(_) => Err(wrong(&join(path, key), "a string")),
    }
}

fn strings(v: &Value, path: &str) -> Read<Vec<String>> {
    array(v, path)?
        .iter()
        .enumerate()
        .map(|(i, s)| {
            s.as_str()
                .map(str::to_string)
                .ok_or_else(|| wrong(&format!("{path}[{i}]"), "a string"))
        })
        .collect()
}
