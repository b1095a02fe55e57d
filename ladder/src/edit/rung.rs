//! The edit operations on one rung's element tree: finding what a path names, inserting
//! beside a selection, wrapping it in a `parallel`, deleting it with the wire closed,
//! and `normalise`, which keeps every rung in the one form the builder draws (no
//! `series` in a `series`, no `parallel` in a `parallel`, none of one element). Knows
//! nothing of the catalog: whether the result is a rung is `json::validate`'s.

use super::path::{ElementPath, Step};
use crate::json::{Element, ModelError, ModelErrorCode as Code};

type Edited<T> = Result<T, ModelError>;

fn no_such(path: &ElementPath, what: &str) -> ModelError {
    ModelError::new(
        Code::NoSuchPath,
        &path.to_string(),
        format!("the rung has no {what} at `{path}`"),
    )
}

fn wrong(path: &ElementPath, message: impl Into<String>) -> ModelError {
    ModelError::new(Code::WrongTarget, &path.to_string(), message)
}

/// The list a step goes into: a series' elements, a parallel's branches, a box's inputs.
fn list_mut(e: &mut Element, step: Step) -> Option<&mut Vec<Element>> {
    match (e, step) {
        (Element::Series { series }, Step::Series(_)) => Some(series),
        (Element::Parallel { parallel }, Step::Parallel(_)) => Some(parallel),
        (Element::Box { inputs, .. }, Step::Input(_)) => Some(inputs),
        _ => None,
    }
}

fn list(e: &Element, step: Step) -> Option<&Vec<Element>> {
    match (e, step) {
        (Element::Series { series }, Step::Series(_)) => Some(series),
        (Element::Parallel { parallel }, Step::Parallel(_)) => Some(parallel),
        (Element::Box { inputs, .. }, Step::Input(_)) => Some(inputs),
        _ => None,
    }
}

/// The element `steps` lead to from `root`.
pub fn element<'a>(root: &'a Element, steps: &[Step]) -> Option<&'a Element> {
    steps
        .iter()
        .try_fold(root, |e, step| list(e, *step)?.get(step.index()))
}

fn element_mut<'a>(root: &'a mut Element, steps: &[Step]) -> Option<&'a mut Element> {
    let mut e = root;
    for step in steps {
        e = list_mut(e, *step)?.get_mut(step.index())?;
    }
    Some(e)
}

/// The element at `path` in `root`, for a change in place (its operands, mnemonic).
pub fn at_mut<'a>(root: &'a mut Element, path: &ElementPath) -> Edited<&'a mut Element> {
    element_mut(root, &path.steps).ok_or_else(|| no_such(path, "element"))
}

/// Checks that `path` and `count` select something: one element anywhere, or a run of
/// `count` elements of one series.
fn selection(root: &Element, path: &ElementPath, count: usize) -> Edited<()> {
    if count == 0 {
        return Err(wrong(path, "a selection has at least one element"));
    }
    if element(root, &path.steps).is_none() {
        return Err(no_such(path, "element"));
    }
    if count == 1 {
        return Ok(());
    }
    let Some((Step::Series(i), parent)) = path.steps.split_last() else {
        return Err(wrong(
            path,
            format!("a selection of {count} elements is a run of one `series`: `{path}` is not in a series"),
        ));
    };
    let len = element(root, parent)
        .and_then(|p| list(p, Step::Series(0)))
        .map_or(0, Vec::len);
    if i.saturating_add(count) > len {
        return Err(no_such(
            path,
            &format!("run of {count} elements (the series has {len})"),
        ));
    }
    Ok(())
}

/// `new` in series before (`before`) or after the selection.
pub fn insert_beside(
    root: &mut Element,
    path: &ElementPath,
    count: usize,
    new: Element,
    before: bool,
) -> Edited<()> {
    selection(root, path, count)?;
    if let Some((Step::Series(i), parent)) = path.steps.split_last() {
        let series = element_mut(root, parent)
            .and_then(|p| list_mut(p, Step::Series(0)))
            .ok_or_else(|| no_such(path, "series"))?;
        let at = if before { *i } else { i + count };
        series.insert(at, new);
        return Ok(());
    }
    let e = at_mut(root, path)?;
    let old = std::mem::replace(e, Element::Series { series: Vec::new() });
    let series = if before {
        vec![new, old]
    } else {
        vec![old, new]
    };
    *e = Element::Series { series };
    Ok(())
}

/// The selection as the upper branch of a `parallel` whose lower branch is `branch`.
pub fn wrap_parallel(
    root: &mut Element,
    path: &ElementPath,
    count: usize,
    branch: Element,
) -> Edited<()> {
    selection(root, path, count)?;
    if let (Some((Step::Series(i), parent)), true) = (path.steps.split_last(), count > 1) {
        let series = element_mut(root, parent)
            .and_then(|p| list_mut(p, Step::Series(0)))
            .ok_or_else(|| no_such(path, "series"))?;
        let run: Vec<Element> = series.drain(*i..i + count).collect();
        let upper = Element::Series { series: run };
        series.insert(
            *i,
            Element::Parallel {
                parallel: vec![upper, branch],
            },
        );
        return Ok(());
    }
    let e = at_mut(root, path)?;
    let old = std::mem::replace(e, Element::Series { series: Vec::new() });
    *e = Element::Parallel {
        parallel: vec![old, branch],
    };
    Ok(())
}

/// The selection deleted; a series or parallel left empty goes too, as far up as that
/// empties. L0016 when that reaches the rung itself; L0015 for a box's power input.
pub fn delete(root: &mut Element, path: &ElementPath, count: usize) -> Edited<()> {
    selection(root, path, count)?;
    let mut steps: &[Step] = &path.steps;
    let mut count = count;
    loop {
        let Some((last, parent)) = steps.split_last() else {
            return Err(ModelError::new(
                Code::LastOutput,
                &path.to_string(),
                "deleting it leaves the network without a rung: delete the network instead",
            ));
        };
        if let Step::Input(_) = last {
            return Err(wrong(
                path,
                "a box's power input is a pin of the box: edit the path inside it, or change the box (`set_mnemonic` with `inputs`)",
            ));
        }
        let items = element_mut(root, parent)
            .and_then(|p| list_mut(p, *last))
            .ok_or_else(|| no_such(path, "element"))?;
        items.drain(last.index()..last.index() + count);
        if !items.is_empty() {
            return Ok(());
        }
        steps = parent;
        count = 1;
    }
}

/// `e` in normal form: series flattened into series and parallels into parallels, a
/// series or parallel of one element replaced by it, everywhere below.
pub fn normalise(e: Element) -> Element {
    match e {
        Element::Series { series } => {
            let mut flat = Vec::with_capacity(series.len());
            for part in series.into_iter().map(normalise) {
                match part {
                    Element::Series { series } => flat.extend(series),
                    other => flat.push(other),
                }
            }
            one_or(flat, |series| Element::Series { series })
        }
        Element::Parallel { parallel } => {
            let mut flat = Vec::with_capacity(parallel.len());
            for part in parallel.into_iter().map(normalise) {
                match part {
                    Element::Parallel { parallel } => flat.extend(parallel),
                    other => flat.push(other),
                }
            }
            one_or(flat, |parallel| Element::Parallel { parallel })
        }
        Element::Box {
            mnemonic,
            operands,
            inputs,
        } => Element::Box {
            mnemonic,
            operands,
            inputs: inputs.into_iter().map(normalise).collect(),
        },
        leaf => leaf,
    }
}

fn one_or(mut list: Vec<Element>, many: fn(Vec<Element>) -> Element) -> Element {
    if list.len() == 1 {
        list.remove(0)
    } else {
        many(list)
    }
}
