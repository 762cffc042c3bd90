//! The types a key's value can have, and how each is shown, written and checked.

use super::human;

/// The type of a key's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ValueType {
    /// A number (float or integer in the file).
    Real,
    /// An integer.
    Integer,
    /// A string.
    Text,
    /// One word of a fixed list.
    Choice(&'static [&'static str]),
    /// An array of numbers.
    RealList,
}

/// A type a key can hold.
pub trait KeyValue: Clone + Sync + 'static {
    /// The type as the registry states it.
    const TYPE: ValueType;
    /// The value as a scene would hold it.
    fn to_toml(&self) -> toml::Value;
    /// The value as a message or the reference spells it.
    fn show(&self) -> String;
    /// The number a range is checked against (`None`: ranges do not apply).
    fn as_number(&self) -> Option<f64> {
        None
    }
}

impl KeyValue for f64 {
    const TYPE: ValueType = ValueType::Real;
    fn to_toml(&self) -> toml::Value {
        toml::Value::Float(*self)
    }
    fn show(&self) -> String {
        human(*self)
    }
    fn as_number(&self) -> Option<f64> {
        Some(*self)
    }
}

impl KeyValue for i64 {
    const TYPE: ValueType = ValueType::Integer;
    fn to_toml(&self) -> toml::Value {
        toml::Value::Integer(*self)
    }
    fn show(&self) -> String {
        self.to_string()
    }
    fn as_number(&self) -> Option<f64> {
        Some(*self as f64)
    }
}

impl KeyValue for String {
    const TYPE: ValueType = ValueType::Text;
    fn to_toml(&self) -> toml::Value {
        toml::Value::String(self.clone())
    }
    fn show(&self) -> String {
        format!("{self:?}")
    }
}

impl KeyValue for Vec<f64> {
    const TYPE: ValueType = ValueType::RealList;
    fn to_toml(&self) -> toml::Value {
        toml::Value::Array(self.iter().map(|v| toml::Value::Float(*v)).collect())
    }
    fn show(&self) -> String {
        format!(
            "[{}]",
            self.iter()
                .map(|v| human(*v))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}

/// A word of a fixed list, as a serde enum whose words are `WORDS` (the serde names, in the
/// reference's order; a test checks both agree).
pub trait Word: serde::Serialize + Copy + Sync + 'static {
    /// Every word, in the order the reference lists them.
    const WORDS: &'static [&'static str];
    /// Every variant, in the order of `WORDS`.
    const ALL: &'static [Self];
}

impl<W: Word> KeyValue for W {
    const TYPE: ValueType = ValueType::Choice(W::WORDS);
    fn to_toml(&self) -> toml::Value {
        toml::Value::try_from(self).unwrap_or_else(|_| toml::Value::String(String::new()))
    }
    fn show(&self) -> String {
        match self.to_toml() {
            toml::Value::String(s) => s,
            other => other.to_string(),
        }
    }
}
