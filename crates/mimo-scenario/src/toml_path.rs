//! The key path of a place in a TOML document (`ships[1].radar.peak_power_w`), so that an error
//! the TOML deserializer reports at a byte offset (a wrong type, a missing field) can name the key
//! as well as the line and column (docs/design.md §7: errors name the file and the key).

use toml::de::{DeTable, DeValue};

/// The dotted key path of the deepest value of `text` whose span holds byte `offset`, or `None`
/// when the text does not parse or the offset lies outside every value (a top-level error).
pub fn key_path_at(text: &str, offset: usize) -> Option<String> {
    let doc = DeTable::parse(text).ok()?;
    let mut path = String::new();
    in_table(doc.get_ref(), offset, &mut path).then_some(path)
}

fn holds(span: &std::ops::Range<usize>, offset: usize) -> bool {
    span.start <= offset && (offset < span.end || span.is_empty() && offset == span.start)
}

/// Push onto `path` the keys leading to the deepest value holding `offset`; whether one does.
fn in_table(t: &DeTable<'_>, offset: usize, path: &mut String) -> bool {
    for (k, v) in t {
        let len = path.len();
        if !path.is_empty() {
            path.push('.');
        }
        path.push_str(k.get_ref());
        // Tables of `[[array]]` headers have no span of their own body: look inside them first.
        if in_value(v.get_ref(), offset, path) || holds(&v.span(), offset) {
            return true;
        }
        path.truncate(len);
    }
    false
}

fn in_value(v: &DeValue<'_>, offset: usize, path: &mut String) -> bool {
    match v {
        DeValue::Table(t) => in_table(t, offset, path),
        DeValue::Array(a) => {
            for (i, e) in a.iter().enumerate() {
                let len = path.len();
                path.push_str(&format!("[{i}]"));
                if in_value(e.get_ref(), offset, path) || holds(&e.span(), offset) {
                    return true;
                }
                path.truncate(len);
            }
            false
        }
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str, needle: &str) -> Option<String> {
        key_path_at(text, text.find(needle).expect("needle"))
    }

    #[test]
    fn a_top_level_value() {
        let t = "name = \"x\"\nduration_s = \"abc\"\n";
        assert_eq!(at(t, "\"abc\"").as_deref(), Some("duration_s"));
    }

    #[test]
    fn values_inside_arrays_of_tables_and_inline_tables() {
        let t =
            "[[ships]]\nid = \"R1\"\n\n[[ships]]\nid = \"R2\"\nlat_deg = \"north\"\nradar = { peak_power_w = true }\n";
        assert_eq!(at(t, "\"north\"").as_deref(), Some("ships[1].lat_deg"));
        assert_eq!(at(t, "true").as_deref(), Some("ships[1].radar.peak_power_w"));
    }

    #[test]
    fn nested_tables_and_plain_arrays() {
        let t = "[aircraft_types.jet]\nrcs_m2 = \"big\"\n[x]\nl = [1, \"two\"]\n";
        assert_eq!(at(t, "\"big\"").as_deref(), Some("aircraft_types.jet.rcs_m2"));
        assert_eq!(at(t, "\"two\"").as_deref(), Some("x.l[1]"));
    }

    #[test]
    fn no_path_outside_every_value_or_in_broken_text() {
        assert_eq!(key_path_at("a = 1\n", 5), None);
        assert_eq!(key_path_at("a = = 1", 0), None);
    }
}
