//! What the cursor is on, found lexically so that hover and completion work while the document is
//! half-typed and does not parse.

/// The word under or just before the cursor, and how it is used.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Word<'a> {
    pub text: &'a str,
    pub start: usize,
    pub end: usize,
    /// Preceded by `.`: a method name.
    pub after_dot: bool,
    /// Followed by `(`: called.
    pub called: bool,
}

fn is_ident_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// The identifier touching `offset` (the cursor may sit just after its last character).
pub fn word_at(text: &str, offset: usize) -> Option<Word<'_>> {
    let bytes = text.as_bytes();
    let offset = offset.min(bytes.len());
    let mut start = offset;
    while start > 0 && is_ident_byte(bytes[start - 1]) {
        start -= 1;
    }
    let mut end = offset;
    while end < bytes.len() && is_ident_byte(bytes[end]) {
        end += 1;
    }
    if start == end || bytes[start].is_ascii_digit() {
        return None;
    }
    let before = text[..start].trim_end_matches([' ', '\t', '\r', '\n']);
    let after = text[end..].trim_start_matches([' ', '\t']);
    Some(Word {
        text: &text[start..end],
        start,
        end,
        after_dot: before.ends_with('.'),
        called: after.starts_with('('),
    })
}

/// The partial identifier ending at `offset` (what the user is typing) and whether it follows a
/// `.`. An empty prefix right after `.` asks for every method.
pub fn prefix_at(text: &str, offset: usize) -> (&str, bool) {
    let bytes = text.as_bytes();
    let offset = offset.min(bytes.len());
    let mut start = offset;
    while start > 0 && is_ident_byte(bytes[start - 1]) {
        start -= 1;
    }
    let before = text[..start].trim_end_matches([' ', '\t', '\r', '\n']);
    (&text[start..offset], before.ends_with('.'))
}

/// Whether `offset` is inside a `//` comment.
pub fn in_comment(text: &str, offset: usize) -> bool {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    text[line_start..offset].contains("//")
}

/// Names bound by `let` anywhere before `offset`, in order of appearance, without duplicates.
pub fn bindings_before(text: &str, offset: usize) -> Vec<&str> {
    let mut out: Vec<&str> = Vec::new();
    let limit = offset.min(text.len());
    for line in text[..limit].lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code.trim_start();
        while let Some(pos) = rest.find("let ") {
            let preceded_ok = pos == 0 || !is_ident_byte(rest.as_bytes()[pos - 1]);
            let after = rest[pos + 4..].trim_start();
            let len = after.bytes().take_while(|&b| is_ident_byte(b)).count();
            if preceded_ok && len > 0 {
                let name = &after[..len];
                if !out.contains(&name) {
                    out.push(name);
                }
            }
            rest = &rest[pos + 4..];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_method_words() {
        let text = "let a = objects(chair).nearest(start)";
        let w = word_at(text, 25).unwrap();
        assert_eq!(w.text, "nearest");
        assert!(w.after_dot && w.called);
        let w = word_at(text, 4).unwrap();
        assert_eq!(w.text, "a");
        assert!(!w.after_dot && !w.called);
    }

    #[test]
    fn prefix_after_dot() {
        assert_eq!(prefix_at("objects(x).ne", 13), ("ne", true));
        assert_eq!(prefix_at("objects(x).", 11), ("", true));
        assert_eq!(prefix_at("let a = obj", 11), ("obj", false));
    }

    #[test]
    fn collects_bindings() {
        let text = "let a = x\n// let b = y\nlet c = a\nroute { let d = c }";
        assert_eq!(bindings_before(text, text.len()), vec!["a", "c", "d"]);
    }
}
