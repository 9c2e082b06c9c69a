//! The values kept from the fields before `kind` ([`Value`], counted by [`Keep`]) and read
//! again once it comes ([`ValueDeserializer`]).

use alloc::boxed::Box;
use alloc::vec::Vec;
use core::fmt;
use core::marker::PhantomData;

use serde::de::value::{MapDeserializer, SeqDeserializer};
use serde::de::{
    self, DeserializeSeed, Deserializer, IntoDeserializer, MapAccess, SeqAccess, Visitor,
};
use serde::forward_to_deserialize_any;

use crate::mesh::{MAX_TRIANGLES, MAX_VERTICES};

/// The most values kept from the fields before `kind` (every number, string and list counts one):
/// enough for the largest valid solid, two meshes at both caps, each vertex and triangle a list of
/// three numbers (4 values), with room for the small fields.
pub(crate) const MAX_KEPT_VALUES: usize = 2 * 4 * (MAX_VERTICES + MAX_TRIANGLES) + (1 << 16);

/// A value kept until the solid's kind is known: what a self-describing format (JSON) gives.
pub(super) enum Value {
    Unit,
    Bool(bool),
    U64(u64),
    I64(i64),
    F64(f64),
    Str(Box<str>),
    Bytes(Box<[u8]>),
    Seq(Box<[Value]>),
    Map(Box<[(Value, Value)]>),
}

/// Reads a [`Value`], counting each against `budget`.
pub(super) struct Keep<'a> {
    pub(super) budget: &'a mut usize,
}

impl Keep<'_> {
    fn count<E: de::Error>(&mut self) -> Result<(), E> {
        *self.budget = self.budget.checked_sub(1).ok_or_else(|| {
            E::custom(format_args!(
                "the solid's fields before its \"kind\" hold more than {MAX_KEPT_VALUES} values \
                 (write \"kind\" first)"
            ))
        })?;
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for Keep<'_> {
    type Value = Value;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Keep<'_> {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("any value")
    }

    fn visit_bool<E: de::Error>(mut self, v: bool) -> Result<Value, E> {
        self.count()?;
        Ok(Value::Bool(v))
    }

    fn visit_i64<E: de::Error>(mut self, v: i64) -> Result<Value, E> {
        self.count()?;
        Ok(Value::I64(v))
    }

    fn visit_u64<E: de::Error>(mut self, v: u64) -> Result<Value, E> {
        self.count()?;
        Ok(Value::U64(v))
    }

    fn visit_f64<E: de::Error>(mut self, v: f64) -> Result<Value, E> {
        self.count()?;
        Ok(Value::F64(v))
    }

    fn visit_str<E: de::Error>(mut self, v: &str) -> Result<Value, E> {
        self.count()?;
        Ok(Value::Str(v.into()))
    }

    fn visit_bytes<E: de::Error>(mut self, v: &[u8]) -> Result<Value, E> {
        self.count()?;
        Ok(Value::Bytes(v.into()))
    }

    fn visit_unit<E: de::Error>(mut self) -> Result<Value, E> {
        self.count()?;
        Ok(Value::Unit)
    }

    fn visit_none<E: de::Error>(self) -> Result<Value, E> {
        self.visit_unit()
    }

    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }

    fn visit_seq<A: SeqAccess<'de>>(mut self, mut seq: A) -> Result<Value, A::Error> {
        self.count()?;
        let mut out = Vec::new();
        while let Some(v) = seq.next_element_seed(Keep {
            budget: self.budget,
        })? {
            out.push(v);
        }
        Ok(Value::Seq(out.into_boxed_slice()))
    }

    fn visit_map<A: MapAccess<'de>>(mut self, mut map: A) -> Result<Value, A::Error> {
        self.count()?;
        let mut out = Vec::new();
        while let Some(k) = map.next_key_seed(Keep {
            budget: self.budget,
        })? {
            let v = map.next_value_seed(Keep {
                budget: self.budget,
            })?;
            out.push((k, v));
        }
        Ok(Value::Map(out.into_boxed_slice()))
    }
}

/// Reads a kept [`Value`] as any type, with the error type of the file's deserializer.
pub(super) struct ValueDeserializer<E> {
    value: Value,
    error: PhantomData<E>,
}

impl<E> ValueDeserializer<E> {
    pub(super) fn new(value: Value) -> Self {
        Self {
            value,
            error: PhantomData,
        }
    }
}

impl<'de, E: de::Error> IntoDeserializer<'de, E> for Value {
    type Deserializer = ValueDeserializer<E>;

    fn into_deserializer(self) -> ValueDeserializer<E> {
        ValueDeserializer::new(self)
    }
}

impl<'de, E: de::Error> Deserializer<'de> for ValueDeserializer<E> {
    type Error = E;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, E> {
        match self.value {
            Value::Unit => visitor.visit_unit(),
            Value::Bool(v) => visitor.visit_bool(v),
            Value::U64(v) => visitor.visit_u64(v),
            Value::I64(v) => visitor.visit_i64(v),
            Value::F64(v) => visitor.visit_f64(v),
            Value::Str(v) => visitor.visit_string(v.into()),
            Value::Bytes(v) => visitor.visit_byte_buf(v.into()),
            Value::Seq(v) => {
                let mut seq = SeqDeserializer::new(v.into_vec().into_iter());
                let out = visitor.visit_seq(&mut seq)?;
                seq.end()?;
                Ok(out)
            }
            Value::Map(v) => {
                let mut map = MapDeserializer::new(v.into_vec().into_iter());
                let out = visitor.visit_map(&mut map)?;
                map.end()?;
                Ok(out)
            }
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, E> {
        match self.value {
            Value::Unit => visitor.visit_none(),
            _ => visitor.visit_some(self),
        }
    }

    forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf unit
        unit_struct newtype_struct seq tuple tuple_struct map struct enum identifier ignored_any
    }
}
