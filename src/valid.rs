//! Checks of a restored (deserialized) state: a state from outside is data, never trusted. Each
//! stage checks its own counters, indices and relations (`check_state` methods next to the
//! data); [`numbers`] walks a whole state through its serde form and checks every number in it
//! at once: finite and of a magnitude no real state reaches ([`MAX_MAGNITUDE`]), so a flipped
//! exponent bit is refused wherever it lands.

use serde::ser::{self, Serialize};
use std::fmt::Display;

/// Largest magnitude of any number in a state (SI). The largest real ones are the parameters a
/// machine allows (axial stiffness ≤ 1e11 N/m, encoder counts ≤ 1e9), times and distances of
/// runs within the engine's 1e9 s.
pub const MAX_MAGNITUDE: f64 = 1e12;

/// Largest machine coordinate of a state (m): programs stay within ±100 m, and work, G92 and
/// tool offsets add at most a few times that.
pub const MAX_POSITION_M: f64 = 1e3;
/// Largest speed of a state (m/s): feeds and axis speeds are at most 1e6 mm/min (16.7 m/s),
/// times the override (2).
pub const MAX_SPEED_M_S: f64 = 1e3;

/// The engine's time range (s): a step ending later is refused, so that tick counts stay exact
/// in f64 (at most 1e14 ticks at the shortest period, 10 µs).
pub const MAX_TIME_S: f64 = 1e9;

/// `x` within [lo, hi] (NaN is not), else the message naming it.
pub fn within(name: &str, x: f64, lo: f64, hi: f64) -> Result<(), String> {
    if x >= lo && x <= hi {
        Ok(())
    } else {
        Err(format!("{name} = {x:e} out of range ({lo:e} … {hi:e})"))
    }
}

/// A count or index `n` at most `max`.
pub fn at_most(name: &str, n: u64, max: u64) -> Result<(), String> {
    if n <= max {
        Ok(())
    } else {
        Err(format!("{name} = {n} out of range (at most {max})"))
    }
}

/// Every finite coordinate of `v` within ±`bound`.
pub fn point(name: &str, v: [f64; 3], bound: f64) -> Result<(), String> {
    v.iter().try_for_each(|&x| within(name, x, -bound, bound))
}

/// A unit vector (to rounding).
pub fn unit_vector(name: &str, v: [f64; 3]) -> Result<(), String> {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    within(&format!("|{name}|"), n, 1.0 - 1e-9, 1.0 + 1e-9)
}

/// What a field (named by the end of its path, e.g. `"v_in_lim"` or `"Hermite.c"`) may hold
/// beyond a finite number within ±[`MAX_MAGNITUDE`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Wider {
    /// NaN or ±∞ as a marker ("not computed yet", "no limit").
    Marker,
    /// Any finite magnitude (polynomial coefficients of tiny pieces).
    Finite,
}

/// Every floating-point number in `value` finite and within ±[`MAX_MAGNITUDE`], except the
/// fields listed in `wider`.
pub fn numbers(value: &impl Serialize, wider: &[(&str, Wider)]) -> Result<(), String> {
    let mut audit = Audit {
        path: Vec::new(),
        wider,
    };
    value.serialize(&mut audit).map_err(|e| e.0)
}

/// The walker: a serde serializer that writes nothing and stops at the first bad number.
struct Audit<'a> {
    path: Vec<&'static str>,
    wider: &'a [(&'a str, Wider)],
}

#[derive(Debug)]
struct Refused(String);

impl Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Refused {}

impl ser::Error for Refused {
    fn custom<T: Display>(msg: T) -> Self {
        Refused(msg.to_string())
    }
}

impl Audit<'_> {
    fn number(&self, x: f64) -> Result<(), Refused> {
        let wider = self.wider.iter().find(|(name, _)| {
            let mut parts = name.rsplit('.');
            let mut path = self.path.iter().rev();
            parts.all(|p| path.next() == Some(&p))
        });
        let ok = match wider.map(|w| w.1) {
            _ if x.abs() <= MAX_MAGNITUDE => true,
            Some(Wider::Marker) => !x.is_finite(),
            Some(Wider::Finite) => x.is_finite(),
            None => false,
        };
        if ok {
            return Ok(());
        }
        Err(Refused(format!("{} = {x:e} out of range", self.path.join("."))))
    }

    fn field<T: Serialize + ?Sized>(&mut self, key: &'static str, value: &T) -> Result<(), Refused> {
        self.path.push(key);
        let r = value.serialize(&mut *self);
        self.path.pop();
        r
    }
}

macro_rules! ignore {
    ($($f:ident($t:ty)),*) => {
        $(fn $f(self, _: $t) -> Result<(), Refused> { Ok(()) })*
    };
}

impl<'a, 'b> ser::Serializer for &'a mut Audit<'b> {
    type Ok = ();
    type Error = Refused;
    type SerializeSeq = Self;
    type SerializeTuple = Self;
    type SerializeTupleStruct = Self;
    type SerializeTupleVariant = Self;
    type SerializeMap = Self;
    type SerializeStruct = Self;
    type SerializeStructVariant = Self;

    ignore!(
        serialize_bool(bool),
        serialize_i8(i8),
        serialize_i16(i16),
        serialize_i32(i32),
        serialize_i64(i64),
        serialize_u8(u8),
        serialize_u16(u16),
        serialize_u32(u32),
        serialize_u64(u64),
        serialize_char(char),
        serialize_str(&str),
        serialize_bytes(&[u8]),
        serialize_unit_struct(&'static str)
    );

    fn serialize_f32(self, x: f32) -> Result<(), Refused> {
        self.number(f64::from(x))
    }
    fn serialize_f64(self, x: f64) -> Result<(), Refused> {
        self.number(x)
    }
    fn serialize_none(self) -> Result<(), Refused> {
        Ok(())
    }
    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> Result<(), Refused> {
        value.serialize(self)
    }
    fn serialize_unit(self) -> Result<(), Refused> {
        Ok(())
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, _: &'static str) -> Result<(), Refused> {
        Ok(())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(self, _: &'static str, v: &T) -> Result<(), Refused> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        value: &T,
    ) -> Result<(), Refused> {
        self.field(variant, value)
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self, Refused> {
        Ok(self)
    }
    fn serialize_tuple(self, _: usize) -> Result<Self, Refused> {
        Ok(self)
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Self, Refused> {
        Ok(self)
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self, Refused> {
        Ok(self)
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self, Refused> {
        Ok(self)
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, Refused> {
        Ok(self)
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self, Refused> {
        Ok(self)
    }
}

macro_rules! elements {
    ($($tr:ident :: $f:ident),*) => {
        $(impl ser::$tr for &mut Audit<'_> {
            type Ok = ();
            type Error = Refused;
            fn $f<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Refused> {
                value.serialize(&mut **self)
            }
            fn end(self) -> Result<(), Refused> {
                Ok(())
            }
        })*
    };
}
elements!(
    SerializeSeq::serialize_element,
    SerializeTuple::serialize_element,
    SerializeTupleStruct::serialize_field,
    SerializeTupleVariant::serialize_field
);

impl ser::SerializeMap for &mut Audit<'_> {
    type Ok = ();
    type Error = Refused;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Refused> {
        key.serialize(&mut **self)
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Refused> {
        value.serialize(&mut **self)
    }
    fn end(self) -> Result<(), Refused> {
        Ok(())
    }
}

macro_rules! fields {
    ($($tr:ident),*) => {
        $(impl ser::$tr for &mut Audit<'_> {
            type Ok = ();
            type Error = Refused;
            fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, value: &T) -> Result<(), Refused> {
                self.field(key, value)
            }
            fn end(self) -> Result<(), Refused> {
                Ok(())
            }
        })*
    };
}
fields!(SerializeStruct, SerializeStructVariant);

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Serialize;

    #[derive(Serialize)]
    struct Inner {
        x: f64,
        limit: f64,
    }
    #[derive(Serialize)]
    struct Outer {
        inner: Vec<Inner>,
        tag: Option<(u32, f64)>,
    }

    #[test]
    fn every_number_is_checked_and_named() {
        let ok = |x: f64, limit: f64, t: f64| Outer {
            inner: vec![Inner { x: 1.0, limit: 2.0 }, Inner { x, limit }],
            tag: Some((7, t)),
        };
        let marker = [("limit", Wider::Marker)];
        assert_eq!(numbers(&ok(3.0, f64::INFINITY, -1e12), &marker), Ok(()));
        assert_eq!(numbers(&ok(3.0, f64::NAN, 0.0), &marker), Ok(()));
        let e = numbers(&ok(-1.3e163, 0.0, 0.0), &marker).unwrap_err();
        assert_eq!(e, "inner.x = -1.3e163 out of range");
        assert!(numbers(&ok(f64::NAN, 0.0, 0.0), &marker).is_err());
        assert!(
            numbers(&ok(0.0, 2e12, 0.0), &marker).is_err(),
            "markers are NaN or ∞, not huge"
        );
        assert!(numbers(&ok(0.0, f64::INFINITY, 0.0), &[]).is_err());
        assert!(numbers(&ok(0.0, 0.0, f64::NEG_INFINITY), &marker).is_err());
        // A path suffix names the field in its place; Finite allows any finite magnitude.
        let finite = [("inner.x", Wider::Finite)];
        assert_eq!(numbers(&ok(-1.3e163, 0.0, 0.0), &finite), Ok(()));
        assert!(numbers(&ok(f64::INFINITY, 0.0, 0.0), &finite).is_err());
        assert!(numbers(&ok(-1.3e163, 0.0, 0.0), &[("outer.x", Wider::Finite)]).is_err());
    }
}
