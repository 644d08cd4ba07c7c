//! Small helpers for writing SVG as text: number formatting and XML escaping.
//!
//! The renderer's contract is "same input, same bytes", so every number goes through [`num`], which
//! rounds to two decimals and never prints `-0`; map names and labels come from users and go
//! through [`esc`].

use std::fmt::Write;

/// Formats a coordinate with at most two decimals and no trailing zeros (`12`, `3.5`, `0.25`).
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return "0".to_string();
    }
    let r = (v * 100.0).round() / 100.0;
    let r = if r == 0.0 { 0.0 } else { r };
    let mut s = format!("{r:.2}");
    while s.ends_with('0') {
        s.pop();
    }
    if s.ends_with('.') {
        s.pop();
    }
    s
}

/// Escapes text for use in element content and in double-quoted attribute values. Control
/// characters that XML 1.0 forbids are dropped, so a hostile label cannot make the SVG unparsable.
pub fn esc(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(' '),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => {}
            c => out.push(c),
        }
    }
    out
}

/// The font stack every text element uses: DejaVu is what the rasterizer finds on Linux, the rest
/// keeps the SVG readable in a browser elsewhere.
pub const FONT: &str = "DejaVu Sans, Arial, Helvetica, sans-serif";

/// Horizontal text alignment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
}

/// Text style for [`text`].
#[derive(Clone, Copy, Debug)]
pub struct TextStyle<'a> {
    pub size: f64,
    pub fill: &'a str,
    pub bold: bool,
    pub anchor: Anchor,
    /// White outline under the glyphs so the text stays readable over busy drawings.
    pub halo: bool,
}

/// Appends one `<text>` element; `y` is the baseline of a vertically centred line.
pub fn text(out: &mut String, x: f64, y: f64, content: &str, st: TextStyle<'_>) {
    let anchor = match st.anchor {
        Anchor::Start => "start",
        Anchor::Middle => "middle",
    };
    let _ = write!(
        out,
        "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{anchor}\" fill=\"{}\"",
        num(x),
        num(y),
        num(st.size),
        st.fill
    );
    if st.bold {
        out.push_str(" font-weight=\"bold\"");
    }
    if st.halo {
        let _ = write!(
            out,
            " stroke=\"#ffffff\" stroke-width=\"{}\" stroke-linejoin=\"round\" paint-order=\"stroke\"",
            num((st.size * 0.28).max(2.0))
        );
    }
    let _ = writeln!(out, ">{}</text>", esc(content));
}

/// Rough width of a text run in DejaVu Sans, used for layout (legend width, label collisions)
/// without measuring glyphs, which keeps layout independent of which fonts are installed.
pub fn text_width(content: &str, size: f64, bold: bool) -> f64 {
    let per_char = if bold { 0.66 } else { 0.6 };
    content.chars().count() as f64 * size * per_char
}

/// Splits `text` into lines no wider than `max_px` at font `size` (by [`text_width`]), breaking
/// at spaces; a word longer than a line gets a line of its own. Explicit newlines are kept.
pub fn wrap(text: &str, max_px: f64, size: f64) -> Vec<String> {
    let max_chars = ((max_px / (size * 0.6)).floor() as usize).max(8);
    let mut lines = Vec::new();
    for para in text.lines() {
        let mut line = String::new();
        for word in para.split_whitespace() {
            if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > max_chars {
                lines.push(std::mem::take(&mut line));
            }
            if !line.is_empty() {
                line.push(' ');
            }
            line.push_str(word);
        }
        lines.push(line);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_stable() {
        assert_eq!(num(12.0), "12");
        assert_eq!(num(3.5), "3.5");
        assert_eq!(num(0.254), "0.25");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(f64::NAN), "0");
        assert_eq!(num(-7.125), "-7.13");
    }

    #[test]
    fn wrapping_breaks_at_spaces_within_the_width() {
        let lines = wrap(
            "go to the bed in the bedroom and then the sofa",
            120.0,
            10.0,
        );
        assert_eq!(
            lines,
            ["go to the bed in the", "bedroom and then the", "sofa"]
        );
        assert_eq!(wrap("a\nb", 600.0, 10.0), ["a", "b"]);
    }

    #[test]
    fn escapes_markup_and_drops_control_characters() {
        assert_eq!(esc("a<b>&\"c'\u{1}"), "a&lt;b&gt;&amp;&quot;c&apos;");
        assert_eq!(esc("x\ny"), "x y");
    }
}
