//! Floating-point figures in JSON without loss, so that a run's `results.json` can be read back
//! (`--resume`, `harness merge`, `harness pareto`) and written out again to the same tables.
//!
//! JSON has no infinity and no NaN. A figure that is NaN (no finite pixel, an empty mask) is
//! written as `null`, as before; an infinite one (the PSNR of identical images) as the string
//! `"inf"` or `"-inf"` instead of a `null` that would read back as "missing". Reading accepts a
//! number, `null` (NaN, or `None` for an optional figure) and those strings, and reads a number
//! from its text with Rust's exact parser (serde_json's own is exact only to within an ulp
//! unless its `float_roundtrip` feature is on, which would change how every crate of the
//! workspace reads JSON): so these fields must be read from JSON text (`serde_json::from_str`),
//! not from a `serde_json::Value`.

use serde::{Deserialize, Deserializer, Serializer};
use serde_json::value::RawValue;

fn from_figure<E: serde::de::Error>(raw: &RawValue) -> Result<Option<f64>, E> {
    match raw.get().trim() {
        "null" => Ok(None),
        "\"inf\"" => Ok(Some(f64::INFINITY)),
        "\"-inf\"" => Ok(Some(f64::NEG_INFINITY)),
        "\"nan\"" | "\"NaN\"" => Ok(Some(f64::NAN)),
        text => text
            .parse::<f64>()
            .map(Some)
            .map_err(|_| E::custom(format!("{text} is not a number"))),
    }
}

fn write<S: Serializer>(v: f64, s: S) -> Result<S::Ok, S::Error> {
    match v {
        v if v.is_nan() => s.serialize_none(),
        f64::INFINITY => s.serialize_str("inf"),
        f64::NEG_INFINITY => s.serialize_str("-inf"),
        v => s.serialize_f64(v),
    }
}

/// `#[serde(with = "json_float::opt")]` for `Option<f64>`: `None` and NaN are `null`.
pub mod opt {
    use super::*;

    pub fn serialize<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(v) => write(*v, s),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
        from_figure(&Box::<RawValue>::deserialize(d)?)
    }
}

/// `#[serde(with = "json_float::num")]` for `f64`: NaN is `null` and reads back as NaN.
pub mod num {
    use super::*;

    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        write(*v, s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(from_figure(&Box::<RawValue>::deserialize(d)?)?.unwrap_or(f64::NAN))
    }
}

#[cfg(test)]
mod tests {
    #[derive(Debug, serde::Serialize, serde::Deserialize)]
    struct Both {
        #[serde(with = "super::opt")]
        a: Option<f64>,
        #[serde(with = "super::num")]
        b: f64,
    }

    fn round_trip(a: Option<f64>, b: f64) -> (String, Both) {
        let text = serde_json::to_string(&Both { a, b }).unwrap();
        let back: Both = serde_json::from_str(&text).unwrap();
        (text, back)
    }

    #[test]
    fn every_figure_reads_back_as_written() {
        let (text, back) = round_trip(Some(f64::INFINITY), f64::NEG_INFINITY);
        assert_eq!(text, r#"{"a":"inf","b":"-inf"}"#);
        assert_eq!((back.a, back.b), (Some(f64::INFINITY), f64::NEG_INFINITY));
        let (text, back) = round_trip(Some(f64::NAN), f64::NAN);
        assert_eq!(text, r#"{"a":null,"b":null}"#);
        assert_eq!(back.a, None, "a NaN figure is written as missing");
        assert!(back.b.is_nan());
        for v in [0.1 + 0.2, 1e-300, -2.5e17, 0.012_345_678_901_234_567] {
            let (_, back) = round_trip(Some(v), v);
            assert_eq!((back.a, back.b), (Some(v), v), "{v} exactly");
        }
        assert!(serde_json::from_str::<Both>(r#"{"a":"x","b":1}"#).is_err());
    }
}
