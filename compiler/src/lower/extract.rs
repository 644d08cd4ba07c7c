//! The program out of a model's reply, or the reason there is none.
//!
//! Accepted, in order: the first fenced block tagged `m2r`; the first untagged fenced block; the
//! whole reply when it reads as a program (a bare reply). Every other reply ends as a distinct
//! outcome the repair loop can answer: no choice at all, a refusal, prose without code, and a reply
//! cut off by the token limit (whatever program text it had is kept for the repair prompt).

use super::ChatReply;
use serde::Serialize;

#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Extracted {
    /// A program to check.
    Code { program: String },
    /// The response had no choice, or the choice had no text.
    Empty,
    /// The model declined (the `refusal` field, a `content_filter` stop, or a reply that only
    /// apologises).
    Refusal { text: String },
    /// Text without a program.
    NoCode { text: String },
    /// `finish_reason: "length"`: the reply stopped at the token limit.
    CutOff { partial: Option<String> },
}

impl Extracted {
    /// A short stable name for records and reports.
    pub fn kind(&self) -> &'static str {
        match self {
            Extracted::Code { .. } => "code",
            Extracted::Empty => "empty_choice",
            Extracted::Refusal { .. } => "refusal",
            Extracted::NoCode { .. } => "no_code",
            Extracted::CutOff { .. } => "cut_off",
        }
    }
}

/// Fenced blocks as (info string, body), in order; an unterminated last fence yields its body
/// with `terminated == false`.
fn fenced_blocks(text: &str) -> Vec<(String, String, bool)> {
    let mut out = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let t = line.trim_start();
        let Some(info) = t.strip_prefix("```") else {
            continue;
        };
        let info = info.trim().to_ascii_lowercase();
        let mut body = Vec::new();
        let mut terminated = false;
        for l in lines.by_ref() {
            if l.trim_start().starts_with("```") {
                terminated = true;
                break;
            }
            body.push(l);
        }
        out.push((info, body.join("\n"), terminated));
    }
    out
}

/// Whether bare text reads as a `.m2r` program rather than prose.
fn looks_like_program(text: &str) -> bool {
    let t = text.trim();
    let has_route = t.contains("route {") || t.contains("route{");
    let first = t.lines().next().unwrap_or("").trim_start();
    has_route
        && (first.starts_with("let ") || first.starts_with("//") || first.starts_with("route"))
}

fn looks_like_refusal(text: &str) -> bool {
    let t = text.trim_start().to_ascii_lowercase();
    [
        "i can't",
        "i cannot",
        "i'm sorry",
        "i am sorry",
        "sorry,",
        "i won't",
        "i am unable",
        "i'm unable",
    ]
    .iter()
    .any(|p| t.starts_with(p))
}

fn normalise(program: &str) -> String {
    let mut p = program.trim_matches('\n').to_string();
    p.push('\n');
    p
}

/// Classifies a reply.
pub fn extract(reply: &ChatReply) -> Extracted {
    if let Some(r) = reply.refusal.as_deref().filter(|r| !r.trim().is_empty()) {
        return Extracted::Refusal {
            text: r.to_string(),
        };
    }
    let content = reply.content.as_deref().unwrap_or("");
    if reply.finish_reason.as_deref() == Some("content_filter") {
        return Extracted::Refusal {
            text: content.to_string(),
        };
    }
    if reply.choices == 0 || content.trim().is_empty() {
        return if reply.finish_reason.as_deref() == Some("length") {
            Extracted::CutOff { partial: None }
        } else {
            Extracted::Empty
        };
    }
    let blocks = fenced_blocks(content);
    let tagged = blocks.iter().find(|(info, _, _)| info == "m2r");
    let untagged = blocks.iter().find(|(info, _, _)| info.is_empty());
    let chosen = tagged.or(untagged);
    if reply.finish_reason.as_deref() == Some("length") {
        let partial = match chosen {
            Some((_, body, _)) => Some(body.clone()),
            None if looks_like_program(content) || content.contains("let ") => {
                Some(content.to_string())
            }
            None => None,
        };
        return Extracted::CutOff {
            partial: partial
                .filter(|p| !p.trim().is_empty())
                .map(|p| normalise(&p)),
        };
    }
    if let Some((_, body, _)) = chosen
        && !body.trim().is_empty()
    {
        return Extracted::Code {
            program: normalise(body),
        };
    }
    if blocks.is_empty() && looks_like_program(content) {
        return Extracted::Code {
            program: normalise(content),
        };
    }
    if looks_like_refusal(content) {
        return Extracted::Refusal {
            text: content.to_string(),
        };
    }
    Extracted::NoCode {
        text: content.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reply(content: &str, finish: &str) -> ChatReply {
        ChatReply {
            choices: 1,
            content: Some(content.into()),
            finish_reason: Some(finish.into()),
            ..ChatReply::default()
        }
    }

    const PROG: &str = "let a = objects(bed).only()\nroute {\n  go a\n}\n";

    #[test]
    fn fenced_untagged_and_bare_programs_are_found() {
        let tagged = format!("Here:\n```python\nx\n```\n```m2r\n{PROG}```\nDone.");
        assert_eq!(
            extract(&reply(&tagged, "stop")),
            Extracted::Code {
                program: PROG.into()
            }
        );
        let plain = format!("```\n{PROG}```");
        assert_eq!(
            extract(&reply(&plain, "stop")),
            Extracted::Code {
                program: PROG.into()
            }
        );
        assert_eq!(
            extract(&reply(PROG, "stop")),
            Extracted::Code {
                program: PROG.into()
            }
        );
    }

    #[test]
    fn each_failure_is_its_own_outcome() {
        let empty = ChatReply::default();
        assert_eq!(extract(&empty), Extracted::Empty);
        assert_eq!(extract(&reply("   ", "stop")), Extracted::Empty);
        let refused = ChatReply {
            refusal: Some("no".into()),
            ..reply("", "stop")
        };
        assert_eq!(extract(&refused).kind(), "refusal");
        assert_eq!(
            extract(&reply("I'm sorry, I can't help with that.", "stop")).kind(),
            "refusal"
        );
        assert_eq!(
            extract(&reply("The chair is in the kitchen.", "stop")).kind(),
            "no_code"
        );
        let cut = extract(&reply(
            "```m2r\nlet a = objects(bed).only()\nroute {\n  go",
            "length",
        ));
        assert_eq!(
            cut,
            Extracted::CutOff {
                partial: Some("let a = objects(bed).only()\nroute {\n  go\n".into())
            }
        );
        assert_eq!(
            extract(&reply("I think", "length")),
            Extracted::CutOff { partial: None }
        );
    }
}
