//! Terminal rendering through codespan-reporting.

use super::{Diagnostic, Severity};
use codespan_reporting::diagnostic as cs;
use codespan_reporting::files::SimpleFile;
use codespan_reporting::term::{self, Config, termcolor};

fn to_codespan(d: &Diagnostic, source: &str) -> cs::Diagnostic<()> {
    let clamp = |s: m2rc_grammar::ast::Span| {
        let end = s.end.min(source.len());
        s.start.min(end)..end
    };
    let severity = match d.severity {
        Severity::Error => cs::Severity::Error,
        Severity::Warning => cs::Severity::Warning,
    };
    let mut labels = vec![cs::Label::primary((), clamp(d.span))];
    labels.extend(
        d.labels
            .iter()
            .map(|l| cs::Label::secondary((), clamp(l.span)).with_message(&l.message)),
    );
    let mut notes = d.notes.clone();
    if let Some(h) = &d.help {
        notes.push(format!("help: {h}"));
    }
    for s in &d.suggestions {
        let at = clamp(s.span);
        let original = source.get(at.clone()).unwrap_or("");
        if original.is_empty() {
            notes.push(format!("suggestion: insert `{}`", s.replacement));
        } else if s.replacement.is_empty() {
            notes.push(format!("suggestion: remove `{original}`"));
        } else {
            notes.push(format!(
                "suggestion: replace `{original}` with `{}`",
                s.replacement
            ));
        }
    }
    cs::Diagnostic::new(severity)
        .with_code(d.code.id())
        .with_message(&d.message)
        .with_labels(labels)
        .with_notes(notes)
}

/// The source with each lone CR (an old Mac line end) read as LF, byte for byte, so spans stay
/// valid and the renderer sees the same lines as `LineIndex`.
fn lines_normalised(source: &str) -> std::borrow::Cow<'_, str> {
    let b = source.as_bytes();
    if !b
        .iter()
        .enumerate()
        .any(|(i, &c)| c == b'\r' && b.get(i + 1) != Some(&b'\n'))
    {
        return std::borrow::Cow::Borrowed(source);
    }
    let mut out = String::with_capacity(source.len());
    let mut chars = source.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '\r' && chars.peek() != Some(&'\n') {
            out.push('\n');
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

/// Plain text, as a terminal without colours or a snapshot test sees it.
pub fn render_text(diags: &[Diagnostic], file_name: &str, source: &str) -> String {
    let source = &*lines_normalised(source);
    let file = SimpleFile::new(file_name, source);
    let config = Config::default();
    let mut out = String::new();
    for d in diags {
        match term::emit_into_string(&config, &file, &to_codespan(d, source)) {
            Ok(s) => out.push_str(&s),
            Err(_) => out.push_str(&format!(
                "{}[{}]: {}\n",
                severity_word(d),
                d.code,
                d.message
            )),
        }
    }
    out
}

/// Text with ANSI colours, for a TTY.
pub fn render_text_colored(diags: &[Diagnostic], file_name: &str, source: &str) -> String {
    let source = &*lines_normalised(source);
    let file = SimpleFile::new(file_name, source);
    let config = Config::default();
    let mut buf = termcolor::Buffer::ansi();
    for d in diags {
        if term::emit_to_write_style(&mut buf, &config, &file, &to_codespan(d, source)).is_err() {
            return render_text(diags, file_name, source);
        }
    }
    String::from_utf8_lossy(buf.as_slice()).into_owned()
}

fn severity_word(d: &Diagnostic) -> &'static str {
    match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    }
}
