//! Labels of a plain-encoded `utf8` column recognised by their stored key
//! ([`crate::page_columns::short_key`]: the value's length and bytes in one integer), so that a
//! page decoder parses each distinct label once and then pays one comparison a row
//! ([`crate::dwell_chunks`]).

use crate::page_columns::PageRowGroup;
use mimo_core::records::{DwellKind, Requester, Role};

/// Labels already parsed, by their stored key ([`crate::page_columns::short_key`]): the last one
/// tried first (runs of equal labels are the rule), then up to [`KeyCache::MAX`] others.
pub(crate) struct KeyCache<T> {
    last: Option<(u128, T)>,
    keys: Vec<(u128, T)>,
}

impl<T> Default for KeyCache<T> {
    fn default() -> Self {
        KeyCache { last: None, keys: Vec::new() }
    }
}

impl<T: Copy> KeyCache<T> {
    /// Keys remembered (more distinct labels are parsed again each time).
    const MAX: usize = 32;

    /// The value of `key`, if seen.
    #[inline]
    pub(crate) fn get(&mut self, key: u128) -> Option<T> {
        if let Some((k, v)) = self.last
            && k == key
        {
            return Some(v);
        }
        let v = self.keys.iter().find(|(k, _)| *k == key).map(|(_, v)| *v)?;
        self.last = Some((key, v));
        Some(v)
    }

    /// `key` parsed to `v`.
    pub(crate) fn insert(&mut self, key: u128, v: T) {
        if self.keys.len() < Self::MAX {
            self.keys.push((key, v));
        }
        self.last = Some((key, v));
    }
}

/// A label column parsed to its enumeration, each distinct stored key parsed once; `None` on a
/// label not of the enumeration.
pub(crate) fn labels<T: Copy + LabelParse>(rg: &PageRowGroup<'_>, col: usize, out: &mut Vec<T>) -> Option<()> {
    out.clear();
    let mut cache = KeyCache::default();
    rg.keyed_strs(col, |key, bytes| {
        let value = match key.and_then(|k| cache.get(k)) {
            Some(v) => v,
            None => {
                let v = T::parse_label(std::str::from_utf8(bytes).ok()?)?;
                if let Some(k) = key {
                    cache.insert(k, v);
                }
                v
            }
        };
        out.push(value);
        Some(())
    })
}

/// An enumeration stored as its labels.
pub(crate) trait LabelParse: Sized {
    /// The value of label `s`, if it is one.
    fn parse_label(s: &str) -> Option<Self>;
}

impl LabelParse for Role {
    fn parse_label(s: &str) -> Option<Self> {
        Role::parse(s)
    }
}

impl LabelParse for DwellKind {
    fn parse_label(s: &str) -> Option<Self> {
        DwellKind::parse(s)
    }
}

impl LabelParse for Requester {
    fn parse_label(s: &str) -> Option<Self> {
        Requester::parse(s)
    }
}
