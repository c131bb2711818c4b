//! Canonical serialisation for hashing: every value a type serialises, with source
//! positions left out by their type.
//!
//! Cache keys and sweep fingerprints must depend on everything that shapes a result and on
//! nothing else. The one thing the IR carries that is not content is where it was written:
//! [`crate::syntax::Span`]. A `Span` identifies itself to serialisers as the newtype struct
//! [`POSITION_TOKEN`] (serde_json and every other serialiser see through a newtype struct, so
//! JSON output is unchanged); this encoder writes a constant marker in its place. Nothing is
//! filtered by field name, so a field called `span` that holds a length (`fins.span`,
//! `fin_point(span = ...)`) is hashed like any other value, and a field added later is
//! hashed without anyone having to remember it.
//!
//! The encoding is self-delimiting (prefix-free): every value starts with a tag byte that
//! fixes its shape, strings and names are length-prefixed, and every sequence, map or struct
//! ends with an end tag distinct from its element tag. Two different values therefore never
//! give the same bytes. Floats are written by their bit pattern (`0.0` and `-0.0` differ; no
//! formatting).

use serde::ser::{self, Serialize};

pub use crate::syntax::span::POSITION_TOKEN;

mod tag {
    pub const BOOL: u8 = 1;
    pub const I64: u8 = 2;
    pub const U64: u8 = 3;
    pub const I128: u8 = 4;
    pub const U128: u8 = 5;
    pub const F32: u8 = 6;
    pub const F64: u8 = 7;
    pub const CHAR: u8 = 8;
    pub const STR: u8 = 9;
    pub const BYTES: u8 = 10;
    pub const NONE: u8 = 11;
    pub const SOME: u8 = 12;
    pub const UNIT: u8 = 13;
    pub const UNIT_STRUCT: u8 = 14;
    pub const UNIT_VARIANT: u8 = 15;
    pub const NEWTYPE_STRUCT: u8 = 16;
    pub const NEWTYPE_VARIANT: u8 = 17;
    pub const SEQ: u8 = 18;
    pub const TUPLE: u8 = 19;
    pub const TUPLE_STRUCT: u8 = 20;
    pub const TUPLE_VARIANT: u8 = 21;
    pub const MAP: u8 = 22;
    pub const STRUCT: u8 = 23;
    pub const STRUCT_VARIANT: u8 = 24;
    pub const ELEMENT: u8 = 25;
    pub const FIELD: u8 = 26;
    pub const SKIPPED_FIELD: u8 = 27;
    pub const END: u8 = 28;
    pub const POSITION: u8 = 29;
}

/// The canonical bytes of a value (source positions replaced by a constant marker).
pub fn to_bytes<T: Serialize + ?Sized>(value: &T) -> Result<Vec<u8>, Error> {
    let mut e = Encoder { out: Vec::new() };
    value.serialize(&mut e)?;
    Ok(e.out)
}

/// blake3 of [`to_bytes`], as 64 hex digits: a fingerprint of a value's content.
pub fn fingerprint<T: Serialize + ?Sized>(value: &T) -> Result<String, Error> {
    Ok(blake3::hash(&to_bytes(value)?).to_hex().to_string())
}

/// A value that could not be encoded (a `Serialize` impl reported an error).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("canonical serialisation failed: {0}")]
pub struct Error(String);

impl ser::Error for Error {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        Error(msg.to_string())
    }
}

struct Encoder {
    out: Vec<u8>,
}

impl Encoder {
    fn tag(&mut self, t: u8) {
        self.out.push(t);
    }
    fn len_bytes(&mut self, b: &[u8]) {
        self.out.extend_from_slice(&(b.len() as u64).to_le_bytes());
        self.out.extend_from_slice(b);
    }
    fn name(&mut self, s: &str) {
        self.len_bytes(s.as_bytes());
    }
}

type R = Result<(), Error>;

impl ser::Serializer for &mut Encoder {
    type Ok = ();
    type Error = Error;
    type SerializeSeq = Self;
    type SerializeTuple = Self;
    type SerializeTupleStruct = Self;
    type SerializeTupleVariant = Self;
    type SerializeMap = Self;
    type SerializeStruct = Self;
    type SerializeStructVariant = Self;

    fn serialize_bool(self, v: bool) -> R {
        self.tag(tag::BOOL);
        self.out.push(u8::from(v));
        Ok(())
    }
    fn serialize_i8(self, v: i8) -> R {
        self.serialize_i64(i64::from(v))
    }
    fn serialize_i16(self, v: i16) -> R {
        self.serialize_i64(i64::from(v))
    }
    fn serialize_i32(self, v: i32) -> R {
        self.serialize_i64(i64::from(v))
    }
    fn serialize_i64(self, v: i64) -> R {
        self.tag(tag::I64);
        self.out.extend_from_slice(&v.to_le_bytes());
        Ok(())
    }
    fn serialize_i128(self, v: i128) -> R {
        self.tag(tag::I128);
        self.out.extend_from_slice(&v.to_le_bytes());
        Ok(())
    }
    fn serialize_u8(self, v: u8) -> R {
        self.serialize_u64(u64::from(v))
    }
    fn serialize_u16(self, v: u16) -> R {
        self.serialize_u64(u64::from(v))
    }
    fn serialize_u32(self, v: u32) -> R {
        self.serialize_u64(u64::from(v))
    }
    fn serialize_u64(self, v: u64) -> R {
        self.tag(tag::U64);
        self.out.extend_from_slice(&v.to_le_bytes());
        Ok(())
    }
    fn serialize_u128(self, v: u128) -> R {
        self.tag(tag::U128);
        self.out.extend_from_slice(&v.to_le_bytes());
        Ok(())
    }
    fn serialize_f32(self, v: f32) -> R {
        self.tag(tag::F32);
        self.out.extend_from_slice(&v.to_bits().to_le_bytes());
        Ok(())
    }
    fn serialize_f64(self, v: f64) -> R {
        self.tag(tag::F64);
        self.out.extend_from_slice(&v.to_bits().to_le_bytes());
        Ok(())
    }
    fn serialize_char(self, v: char) -> R {
        self.tag(tag::CHAR);
        self.out.extend_from_slice(&u32::from(v).to_le_bytes());
        Ok(())
    }
    fn serialize_str(self, v: &str) -> R {
        self.tag(tag::STR);
        self.name(v);
        Ok(())
    }
    fn serialize_bytes(self, v: &[u8]) -> R {
        self.tag(tag::BYTES);
        self.len_bytes(v);
        Ok(())
    }
    fn serialize_none(self) -> R {
        self.tag(tag::NONE);
        Ok(())
    }
    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> R {
        self.tag(tag::SOME);
        value.serialize(self)
    }
    fn serialize_unit(self) -> R {
        self.tag(tag::UNIT);
        Ok(())
    }
    fn serialize_unit_struct(self, name: &'static str) -> R {
        self.tag(tag::UNIT_STRUCT);
        self.name(name);
        Ok(())
    }
    fn serialize_unit_variant(self, name: &'static str, _index: u32, variant: &'static str) -> R {
        self.tag(tag::UNIT_VARIANT);
        self.name(name);
        self.name(variant);
        Ok(())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(self, name: &'static str, value: &T) -> R {
        if name == POSITION_TOKEN {
            // Where a value was written is not part of it.
            self.tag(tag::POSITION);
            return Ok(());
        }
        self.tag(tag::NEWTYPE_STRUCT);
        self.name(name);
        value.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        name: &'static str,
        _index: u32,
        variant: &'static str,
        value: &T,
    ) -> R {
        self.tag(tag::NEWTYPE_VARIANT);
        self.name(name);
        self.name(variant);
        value.serialize(self)
    }
    fn serialize_seq(self, _len: Option<usize>) -> Result<Self, Error> {
        self.tag(tag::SEQ);
        Ok(self)
    }
    fn serialize_tuple(self, _len: usize) -> Result<Self, Error> {
        self.tag(tag::TUPLE);
        Ok(self)
    }
    fn serialize_tuple_struct(self, name: &'static str, _len: usize) -> Result<Self, Error> {
        self.tag(tag::TUPLE_STRUCT);
        self.name(name);
        Ok(self)
    }
    fn serialize_tuple_variant(
        self,
        name: &'static str,
        _index: u32,
        variant: &'static str,
        _len: usize,
    ) -> Result<Self, Error> {
        self.tag(tag::TUPLE_VARIANT);
        self.name(name);
        self.name(variant);
        Ok(self)
    }
    fn serialize_map(self, _len: Option<usize>) -> Result<Self, Error> {
        self.tag(tag::MAP);
        Ok(self)
    }
    fn serialize_struct(self, name: &'static str, _len: usize) -> Result<Self, Error> {
        self.tag(tag::STRUCT);
        self.name(name);
        Ok(self)
    }
    fn serialize_struct_variant(
        self,
        name: &'static str,
        _index: u32,
        variant: &'static str,
        _len: usize,
    ) -> Result<Self, Error> {
        self.tag(tag::STRUCT_VARIANT);
        self.name(name);
        self.name(variant);
        Ok(self)
    }
}

impl Encoder {
    fn element<T: Serialize + ?Sized>(&mut self, value: &T) -> R {
        self.tag(tag::ELEMENT);
        value.serialize(self)
    }
    fn field<T: Serialize + ?Sized>(&mut self, key: &'static str, value: &T) -> R {
        self.tag(tag::FIELD);
        self.name(key);
        value.serialize(self)
    }
    fn end(&mut self) -> R {
        self.tag(tag::END);
        Ok(())
    }
}

impl ser::SerializeSeq for &mut Encoder {
    type Ok = ();
    type Error = Error;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, value: &T) -> R {
        self.element(value)
    }
    fn end(self) -> R {
        Encoder::end(self)
    }
}

impl ser::SerializeTuple for &mut Encoder {
    type Ok = ();
    type Error = Error;
    fn serialize_element<T: Serialize + ?Sized>(&mut self, value: &T) -> R {
        self.element(value)
    }
    fn end(self) -> R {
        Encoder::end(self)
    }
}

impl ser::SerializeTupleStruct for &mut Encoder {
    type Ok = ();
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, value: &T) -> R {
        self.element(value)
    }
    fn end(self) -> R {
        Encoder::end(self)
    }
}

impl ser::SerializeTupleVariant for &mut Encoder {
    type Ok = ();
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, value: &T) -> R {
        self.element(value)
    }
    fn end(self) -> R {
        Encoder::end(self)
    }
}

impl ser::SerializeMap for &mut Encoder {
    type Ok = ();
    type Error = Error;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> R {
        self.element(key)
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, value: &T) -> R {
        value.serialize(&mut **self)
    }
    fn end(self) -> R {
        Encoder::end(self)
    }
}

impl ser::SerializeStruct for &mut Encoder {
    type Ok = ();
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, value: &T) -> R {
        self.field(key, value)
    }
    fn skip_field(&mut self, key: &'static str) -> R {
        self.tag(tag::SKIPPED_FIELD);
        self.name(key);
        Ok(())
    }
    fn end(self) -> R {
        Encoder::end(self)
    }
}

impl ser::SerializeStructVariant for &mut Encoder {
    type Ok = ();
    type Error = Error;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, value: &T) -> R {
        self.field(key, value)
    }
    fn skip_field(&mut self, key: &'static str) -> R {
        self.tag(tag::SKIPPED_FIELD);
        self.name(key);
        Ok(())
    }
    fn end(self) -> R {
        Encoder::end(self)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::syntax::{FileId, Span, Spanned};

    #[derive(serde::Serialize)]
    struct T {
        span: f64,
        at: Span,
        v: Spanned<Vec<String>>,
    }

    #[test]
    fn positions_are_left_out_by_type_and_values_named_span_are_kept() {
        let s = |a, b| Span::new(FileId(a), b, b + 3);
        let t = |span, p: Span, v: &[&str]| T {
            span,
            at: p,
            v: Spanned::new(v.iter().map(|x| x.to_string()).collect(), p),
        };
        let base = to_bytes(&t(0.12, s(0, 4), &["a", "bc"])).unwrap();
        assert_eq!(base, to_bytes(&t(0.12, s(3, 40), &["a", "bc"])).unwrap());
        assert_ne!(base, to_bytes(&t(0.24, s(0, 4), &["a", "bc"])).unwrap());
        assert_ne!(base, to_bytes(&t(-0.0, s(0, 4), &["a", "bc"])).unwrap());
        assert_ne!(
            to_bytes(&t(0.0, s(0, 4), &["a"])).unwrap(),
            to_bytes(&t(-0.0, s(0, 4), &["a"])).unwrap()
        );
        // Prefix-free: moving a character between elements changes the bytes.
        assert_ne!(base, to_bytes(&t(0.12, s(0, 4), &["ab", "c"])).unwrap());
        assert_ne!(base, to_bytes(&t(0.12, s(0, 4), &["a", "bc", ""])).unwrap());
        // JSON still shows the position.
        let json = serde_json::to_string(&s(1, 2)).unwrap();
        assert_eq!(json, "[1,2,5]");
    }
}
