//! The stock benchmark hands and objects by name, and user ones by path: what `--hand NAME|PATH`
//! and `--object NAME|PATH` accept.
//!
//! A name of [`HAND_NAMES`] / [`OBJECT_NAMES`] gives the stock model of `opengrasp-assets`;
//! anything else is a path: a hand spec file naming its URDF ([`Hand::load`]) or an object's
//! mesh or metadata file ([`ObjectModel::load`]).

use std::path::Path;

use opengrasp_assets::{hands, objects};
use opengrasp_core::hand::Hand;
use opengrasp_core::object::ObjectModel;

use crate::error::{Error, Result};

/// Names of the stock benchmark hands: the ARMAR-III hand (paper Table I), the Barrett BH8-262
/// (Table II) and the Schunk SDH.
pub const HAND_NAMES: [&str; 3] = ["armar3", "barrett", "sdh"];

/// Names of the stock objects (the KIT kitchen objects of `opengrasp-assets`).
pub const OBJECT_NAMES: [&str; 9] = objects::NAMES;

/// A stock benchmark hand, named as in results (`"barrett"`, ...).
///
/// # Errors
/// [`Error::InvalidOption`] for a name not in [`HAND_NAMES`].
pub fn stock_hand(name: &str) -> Result<Hand> {
    let hand = match name {
        "armar3" => hands::armar3_hand(),
        "barrett" => hands::barrett(),
        "sdh" => hands::sdh(),
        _ => return Err(unknown("hand", name, &HAND_NAMES)),
    };
    Ok(hand.with_name(name))
}

/// A stock object by name.
///
/// # Errors
/// [`Error::InvalidOption`] for a name not in [`OBJECT_NAMES`].
pub fn stock_object(name: &str) -> Result<ObjectModel> {
    if !OBJECT_NAMES.contains(&name) {
        return Err(unknown("object", name, &OBJECT_NAMES));
    }
    Ok(objects::by_name(name)?)
}

/// A stock hand by name, else a hand spec file at that path.
///
/// # Errors
/// [`Error::InvalidOption`] if it is neither a stock name nor an existing file; the loader's
/// errors ([`Error::Core`]) for a file that is not a valid hand.
pub fn resolve_hand(name_or_path: &str) -> Result<Hand> {
    resolve(name_or_path, "hand", &HAND_NAMES, stock_hand, |p| Hand::load(p))
}

/// A stock object by name, else an object mesh or metadata file at that path.
///
/// # Errors
/// As [`resolve_hand`].
pub fn resolve_object(name_or_path: &str) -> Result<ObjectModel> {
    resolve(name_or_path, "object", &OBJECT_NAMES, stock_object, |p| ObjectModel::load(p))
}

fn resolve<T>(
    name_or_path: &str,
    what: &'static str,
    stock_names: &[&str],
    stock: impl Fn(&str) -> Result<T>,
    load: impl Fn(&Path) -> opengrasp_core::Result<T>,
) -> Result<T> {
    if stock_names.contains(&name_or_path) {
        return stock(name_or_path);
    }
    let path = Path::new(name_or_path);
    if !path.is_file() {
        return Err(unknown(what, name_or_path, stock_names));
    }
    Ok(load(path)?)
}

fn unknown(what: &'static str, name: &str, known: &[&str]) -> Error {
    Error::InvalidOption {
        name: what,
        reason: format!("`{name}` is neither a stock {what} ({}) nor a file", known.join(", ")),
    }
}
