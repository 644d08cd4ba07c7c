//! The `.m2r` type language and the table of built-ins with their typed signatures.
//!
//! [`table::BUILTINS`] is the single source for the type checker, the generated language reference,
//! hover text and the LLM prompt.

pub mod signature;
pub mod statements;
pub mod synonyms;
pub mod table;
mod table_parts;
pub mod types;

pub use signature::{
    Builtin, Constant, DefaultValue, Direction, EnumWord, Metric, Param, Receiver, Requirement, Ty,
};
pub use statements::STATEMENTS;
pub use table::{BUILTINS, CONSTANTS, ENUM_WORDS};
pub use types::{Elem, Scalar, Type};

/// Every row with this name called as a free function.
pub fn functions(name: &str) -> impl Iterator<Item = &'static Builtin> + '_ {
    BUILTINS
        .iter()
        .filter(move |b| b.name == name && !b.is_method())
}

/// Every row with this name called as a method, whatever the receiver.
pub fn methods(name: &str) -> impl Iterator<Item = &'static Builtin> + '_ {
    BUILTINS
        .iter()
        .filter(move |b| b.name == name && b.is_method())
}

/// The method overload whose receiver accepts `recv`, with `T` bound.
pub fn method_for(name: &str, recv: Type) -> Option<(&'static Builtin, Elem)> {
    methods(name).find_map(|b| b.bind_receiver(recv).map(|t| (b, t)))
}

pub fn constant(name: &str) -> Option<&'static Constant> {
    CONSTANTS.iter().find(|c| c.name == name)
}

pub fn enum_word(name: &str) -> Option<&'static EnumWord> {
    ENUM_WORDS.iter().find(|w| w.name == name)
}

/// Distinct names of free functions, methods, constants and enumeration words, for did-you-mean.
pub fn all_names() -> Vec<&'static str> {
    let mut v: Vec<&'static str> = BUILTINS.iter().map(|b| b.name).collect();
    v.extend(CONSTANTS.iter().map(|c| c.name));
    v.extend(ENUM_WORDS.iter().map(|w| w.name));
    v.sort_unstable();
    v.dedup();
    v
}

/// A compact plain-text listing (one built-in per line: signature, doc) for LLM prompts.
pub fn prompt_reference() -> String {
    let mut out = String::new();
    for b in BUILTINS {
        out.push_str(&format!("{}  // {}\n", b.signature(None), b.doc));
    }
    for c in CONSTANTS {
        out.push_str(&format!("{}: {}  // {}\n", c.name, c.ty, c.doc));
    }
    for w in ENUM_WORDS {
        out.push_str(&format!("{}: {}  // {}\n", w.name, w.ty, w.doc));
    }
    for s in STATEMENTS {
        for f in s.forms {
            out.push_str(&format!("{}  // {}\n", s.form_line(f), f.doc));
        }
    }
    out
}

/// Hover text for a name: every row with that name (all overloads), or the constant or word.
pub fn hover(name: &str) -> Option<String> {
    let rows: Vec<String> = BUILTINS
        .iter()
        .filter(|b| b.name == name)
        .map(|b| format!("`{}`\n{}", b.signature(None), b.doc))
        .collect();
    if !rows.is_empty() {
        return Some(rows.join("\n\n"));
    }
    if let Some(c) = constant(name) {
        return Some(format!("`{}: {}`\n{}", c.name, c.ty, c.doc));
    }
    enum_word(name).map(|w| format!("`{}: {}`\n{}", w.name, w.ty, w.doc))
}

/// The language reference section for the built-ins, as Markdown; generated so that it cannot
/// drift from the table.
pub fn reference_markdown() -> String {
    let mut out = String::new();
    out.push_str("| Signature | Description | Example |\n|---|---|---|\n");
    for b in BUILTINS {
        out.push_str(&format!(
            "| `{}` | {} | `{}` |\n",
            b.signature(None).replace('|', "\\|"),
            b.doc.replace('|', "\\|"),
            b.example.replace('|', "\\|")
        ));
    }
    out.push_str("\n| Constant | Type | Description |\n|---|---|---|\n");
    for c in CONSTANTS {
        out.push_str(&format!("| `{}` | `{}` | {} |\n", c.name, c.ty, c.doc));
    }
    out.push_str("\n| Word | Type | Description |\n|---|---|---|\n");
    for w in ENUM_WORDS {
        out.push_str(&format!("| `{}` | `{}` | {} |\n", w.name, w.ty, w.doc));
    }
    out.push_str("\n| Statement | Description | Example |\n|---|---|---|\n");
    for s in STATEMENTS {
        for f in s.forms {
            out.push_str(&format!(
                "| `{}` | {} | `{}` |\n",
                s.form_line(f).replace('|', "\\|"),
                f.doc.replace('|', "\\|"),
                f.example
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overloads_are_picked_by_receiver() {
        let (b, t) = method_for("near", Type::Set(Elem::Object)).unwrap();
        assert_eq!(b.ret.instantiate(t), Some(Type::Set(Elem::Object)));
        let (b, _) = method_for("near", Type::Object).unwrap();
        assert_eq!(b.ret, Ty::Is(Type::Bool));
        assert_eq!(
            functions("near").next().unwrap().ret,
            Ty::Is(Type::Preference)
        );
        assert!(method_for("nearest", Type::Object).is_none());
        let (b, t) = method_for("nearest", Type::Set(Elem::Room)).unwrap();
        assert_eq!(b.ret.instantiate(t), Some(Type::Room));
        // Objects rank by footprint area, rooms by floor area: two rows, one name.
        assert!(method_for("largest", Type::Set(Elem::Object)).is_some());
        assert!(method_for("largest", Type::Set(Elem::Region)).is_none());
    }

    #[test]
    fn signatures_render_with_defaults_and_bound_t() {
        let b = methods("nearest").next().unwrap();
        assert_eq!(
            b.signature(Some(Elem::Object)),
            "Set<Object>.nearest(to: Place | Set<Place> = here, by: Metric = straight) -> Object"
        );
        let o = functions("objects").next().unwrap();
        assert_eq!(
            o.signature(None),
            "objects(category: Category?) -> Set<Object>"
        );
    }

    #[test]
    fn prompt_and_hover_come_from_the_table() {
        let prompt = prompt_reference();
        let forms: usize = STATEMENTS.iter().map(|s| s.forms.len()).sum();
        assert_eq!(
            prompt.lines().count(),
            BUILTINS.len() + CONSTANTS.len() + ENUM_WORDS.len() + forms
        );
        assert!(prompt.contains("rooms(category: Category?) -> Set<Room>  // All rooms"));
        // The set forms of `go` and `pass` (issue 35, item 6) are lines of the table.
        assert!(prompt.contains("go <Set<Place>>  // A stage to any one of the places"));
        assert!(prompt.contains("pass <Set<Place>>  // Inside a stage"));
        for s in STATEMENTS {
            assert!(statements::operand(s.keyword).contains(&Ty::SET_PLACE));
        }
        let near = hover("near").unwrap();
        assert_eq!(near.matches("near(").count(), 3, "{near}");
        assert!(hover("here").unwrap().contains("Region"));
        assert!(hover("nothing_like_this").is_none());
    }

    #[test]
    fn table_is_consistent() {
        let mut seen = std::collections::HashSet::new();
        for b in BUILTINS {
            let key = (b.name, format!("{:?}", b.receiver));
            assert!(seen.insert(key), "duplicate row {}", b.name);
            assert!(
                !b.doc.is_empty() && b.doc.ends_with('.'),
                "doc of {}",
                b.name
            );
            assert!(!b.example.is_empty());
            // Required parameters come before optional ones, so positional calls stay unambiguous.
            let first_opt = b.params.iter().position(|p| p.req != Requirement::Required);
            if let Some(i) = first_opt {
                assert!(
                    b.params[i..].iter().all(|p| p.req != Requirement::Required),
                    "{}",
                    b.name
                );
            }
        }
        for c in CONSTANTS {
            assert!(functions(c.name).next().is_none());
        }
    }
}

#[cfg(test)]
mod doc_tests {
    /// The built-in section of `docs/language-design.md` is generated from the table.
    #[test]
    fn builtins_doc_is_current() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/language-design.md");
        let Ok(text) = std::fs::read_to_string(path) else {
            panic!("cannot read {path}")
        };
        let (start, end) = ("<!-- builtins:start -->\n", "<!-- builtins:end -->");
        let (Some(a), Some(b)) = (text.find(start), text.find(end)) else {
            panic!("markers missing in {path}")
        };
        let want = super::reference_markdown();
        if std::env::var_os("UPDATE_DOCS").is_some() {
            let new = format!("{}{}{}{}", &text[..a + start.len()], want, "", &text[b..]);
            std::fs::write(path, new).unwrap();
            return;
        }
        assert!(
            text[a + start.len()..b] == want,
            "the built-in table in docs/language-design.md is stale: run `UPDATE_DOCS=1 cargo test -p m2rc-stdlib builtins_doc`"
        );
    }
}
