//! Reading values handed in from JavaScript strictly: a number must be a
//! JS number (no coercion of strings, BigInts or objects), a count a whole
//! number in its range, a seed a u64 held exactly, and an exception thrown
//! while reading (a getter, a `Proxy` trap) comes back as [`Error::Threw`]
//! instead of being taken for a missing value. Every export reads its
//! numbers, counts and seeds through here.

use wasm_bindgen::prelude::*;

use crate::error::{Error, Given};

/// `object[key]`; a throw while reading it is [`Error::Threw`] naming `key`.
pub(crate) fn get(object: &JsValue, key: &'static str) -> Result<JsValue, Error> {
    get_as(object, key, key)
}

/// `object[key]` as [`get`], a throw named `name` (a part of a setting,
/// such as the `length` of `centre`, is reported as the setting).
pub(crate) fn get_as(
    object: &JsValue,
    key: &'static str,
    name: &'static str,
) -> Result<JsValue, Error> {
    js_sys::Reflect::get(object, &JsValue::from_str(key)).map_err(|e| threw(name, &e))
}

/// `array[index]`, as [`get`], a throw named `name`.
pub(crate) fn get_index(array: &JsValue, index: u32, name: &'static str) -> Result<JsValue, Error> {
    js_sys::Reflect::get_u32(array, index).map_err(|e| threw(name, &e))
}

#[wasm_bindgen]
extern "C" {
    /// `Array.isArray`, which throws on a revoked `Proxy`: caught, unlike
    /// js-sys's binding, so that nothing thrown crosses the wasm frames
    /// unhandled.
    #[wasm_bindgen(js_namespace = Array, js_name = isArray, catch)]
    fn array_is_array(value: &JsValue) -> Result<bool, JsValue>;
}

/// Whether `value` is an array (a `Proxy` of one included); a throw is
/// [`Error::Threw`] naming `name`.
pub(crate) fn is_array(value: &JsValue, name: &'static str) -> Result<bool, Error> {
    array_is_array(value).map_err(|e| threw(name, &e))
}

/// Refuses an object with an own string key outside `known`: a misspelt
/// setting is an error, not a default. Symbol keys are not settings and
/// are left alone.
pub(crate) fn only_keys(
    object: &JsValue,
    known: &'static [&'static str],
    name: &'static str,
) -> Result<(), Error> {
    let keys = js_sys::Reflect::own_keys(object).map_err(|e| threw(name, &e))?;
    for key in keys.iter() {
        if let Some(key) = key.as_string()
            && !known.contains(&key.as_str())
        {
            return Err(Error::UnknownSetting {
                key,
                known,
                within: name,
            });
        }
    }
    Ok(())
}

/// `value` when it is a JS number (NaN and infinities included: the
/// kernel judges ranges).
pub(crate) fn number(value: &JsValue, name: &'static str) -> Result<f64, Error> {
    value.as_f64().ok_or(Error::NotANumber(name))
}

/// `value` when it is a JS number holding a whole number in `min..=max`
/// (`max` at most `2^53 - 1`, so the number is exact). `-0` is 0.
pub(crate) fn count(value: &JsValue, name: &'static str, min: u64, max: u64) -> Result<u64, Error> {
    match value.as_f64() {
        Some(v) if v.fract() == 0.0 && v >= min as f64 && v <= max as f64 => Ok(v as u64),
        _ => Err(Error::NotACount {
            name,
            given: given(value),
            min,
            max,
        }),
    }
}

/// Largest integer a JS number holds exactly, `2^53 - 1`.
const MAX_SAFE_INTEGER: f64 = 9_007_199_254_740_991.0;

/// `v` as a u64 when it is a whole number in `0..=2^53 - 1`, where the
/// conversion is exact.
pub(crate) fn safe_whole(v: f64) -> Option<u64> {
    ((0.0..=MAX_SAFE_INTEGER).contains(&v) && v.fract() == 0.0).then_some(v as u64)
}

/// A seed, a u64: a JS number when it is a whole number up to `2^53 - 1`
/// (so it is exact), a BigInt for the full range; anything else is
/// [`Error::BadSeed`].
pub(crate) fn seed(value: &JsValue) -> Result<u64, Error> {
    if value.is_bigint() {
        return u64::try_from(value.clone()).map_err(|_| Error::BadSeed);
    }
    value.as_f64().and_then(safe_whole).ok_or(Error::BadSeed)
}

/// What `value` is, for a message that refuses it where a number was
/// asked for. Reads nothing of an object (no getter runs).
fn given(value: &JsValue) -> Given {
    if let Some(v) = value.as_f64() {
        return Given::Number(v);
    }
    if let Some(big) = value.dyn_ref::<js_sys::BigInt>() {
        // A sign and 20 digits hold every 64-bit integer.
        return match big.to_string(10).ok().map(String::from) {
            Some(digits) if digits.len() <= 21 => Given::BigInt(digits),
            Some(digits) => Given::LongBigInt(digits.len()),
            None => Given::Other("a BigInt"),
        };
    }
    Given::Other(if value.is_string() {
        "a string"
    } else if value.is_undefined() {
        "undefined"
    } else if value.is_null() {
        "null"
    } else if value.as_bool().is_some() {
        "a boolean"
    } else if value.is_symbol() {
        "a symbol"
    } else if value.is_function() {
        "a function"
    } else {
        "an object"
    })
}

/// An array of exactly four JS numbers (a box `[x0, x1, y0, y1]`); else
/// [`Error::BadBox`].
pub(crate) fn four(value: &JsValue, name: &'static str) -> Result<[f64; 4], Error> {
    if !is_array(value, name)? || get_as(value, "length", name)?.as_f64() != Some(4.0) {
        return Err(Error::BadBox);
    }
    let mut out = [0.0; 4];
    for (i, v) in (0_u32..).zip(out.iter_mut()) {
        *v = get_index(value, i, name)?.as_f64().ok_or(Error::BadBox)?;
    }
    Ok(out)
}

/// [`Error::Threw`] for `thrown`, with its message.
fn threw(field: &'static str, thrown: &JsValue) -> Error {
    Error::Threw {
        field,
        message: message_of(thrown),
    }
}

/// The message of a thrown value, read without running any more of the
/// thrower's code than one property read (no `toString`, no `instanceof`,
/// which a `Proxy` can also make throw): an `Error`'s `message` when it is
/// a string, a thrown string or number itself, else a placeholder.
fn message_of(thrown: &JsValue) -> String {
    if let Some(s) = thrown.as_string() {
        return s;
    }
    if let Some(v) = thrown.as_f64() {
        return v.to_string();
    }
    if thrown.is_object() {
        // Reading `message` may itself throw: the placeholder then.
        let message = js_sys::Reflect::get(thrown, &JsValue::from_str("message"))
            .ok()
            .and_then(|m| m.as_string());
        if let Some(m) = message {
            return m;
        }
    }
    "a thrown value without a message".into()
}
