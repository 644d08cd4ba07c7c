//! Reading LIMP's stage-2 formula: every `near[...]` predicate becomes an atom of m2rc's infix
//! LTLf syntax, and each argument a composable referent descriptor (CRD): a noun, optionally
//! refined as `noun::predicate(arg, ...)` (arguments may be CRDs themselves, nested a few deep).

use m2rc_compiler::ltl::Formula;
use serde::Serialize;

/// Deepest CRD nesting read.
const MAX_CRD_DEPTH: usize = 4;
/// Most predicates read from one formula.
const MAX_PREDICATES: usize = 32;

/// A referent descriptor.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Crd {
    pub noun: String,
    /// `(predicate, arguments)`, when refined.
    pub relation: Option<(String, Vec<Crd>)>,
}

impl std::fmt::Display for Crd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.noun)?;
        if let Some((p, args)) = &self.relation {
            let a: Vec<String> = args.iter().map(|c| c.to_string()).collect();
            write!(f, "::{p}({})", a.join(","))?;
        }
        Ok(())
    }
}

/// A parsed stage-2 formula: the formula over atoms `p0, p1, ...` and the CRD of each atom.
#[derive(Clone, Debug)]
pub struct Encoded {
    pub formula: Formula,
    pub predicates: Vec<(String, Crd)>,
}

/// Reads `reply` (its last non-empty line outside a code fence).
pub fn parse_stage2(reply: &str) -> Result<Encoded, String> {
    let line = reply
        .lines()
        .map(str::trim)
        .rfind(|l| !l.is_empty() && !l.starts_with("```"))
        .ok_or("the output is empty")?;
    let line = line.strip_prefix("Output:").unwrap_or(line).trim();
    let mut text = String::new();
    let mut predicates: Vec<(String, Crd)> = vec![];
    let mut rest = line;
    while let Some(i) = rest.find("near[") {
        text.push_str(&rest[..i]);
        let after = &rest[i + 5..];
        let close = matching_bracket(after).ok_or_else(|| {
            format!(
                "`near[` at `{}` is never closed",
                &rest[i..rest.len().min(i + 30)]
            )
        })?;
        let inner = after[..close].trim();
        let crd = parse_crd(inner, 0)?;
        let name = match predicates.iter().find(|(_, c)| *c == crd) {
            Some((n, _)) => n.clone(),
            None => {
                if predicates.len() >= MAX_PREDICATES {
                    return Err(format!("more than {MAX_PREDICATES} near[...] predicates"));
                }
                let n = format!("p{}", predicates.len());
                predicates.push((n.clone(), crd));
                n
            }
        };
        text.push_str(&format!(" {name} "));
        rest = &after[close + 1..];
    }
    text.push_str(rest);
    if predicates.is_empty() {
        return Err("no complete near[...] predicate".into());
    }
    if text.contains('[') || text.contains(']') {
        return Err("bracket text is left outside the near[...] predicates".into());
    }
    let formula = m2rc_compiler::ltl::parse(&text).map_err(|e| e.message)?;
    for a in formula.atoms() {
        if !predicates.iter().any(|(n, _)| n == a) {
            return Err(format!(
                "`{a}` is a bare proposition, not a near[...] predicate"
            ));
        }
    }
    Ok(Encoded {
        formula,
        predicates,
    })
}

fn matching_bracket(s: &str) -> Option<usize> {
    let mut depth = 0usize;
    for (i, c) in s.char_indices() {
        match c {
            '[' => depth += 1,
            ']' if depth == 0 => return Some(i),
            ']' => depth -= 1,
            _ => {}
        }
    }
    None
}

/// A CRD: `noun` or `noun::pred(arg, ...)`.
pub fn parse_crd(s: &str, depth: usize) -> Result<Crd, String> {
    if depth > MAX_CRD_DEPTH {
        return Err(format!("a referent nests deeper than {MAX_CRD_DEPTH}"));
    }
    let s = s.trim();
    let Some((noun, pred)) = s.split_once("::") else {
        if s.is_empty() || s.contains(['(', ')', ',']) {
            return Err(format!("`{s}` is not a referent"));
        }
        return Ok(Crd {
            noun: s.to_string(),
            relation: None,
        });
    };
    let open = pred
        .find('(')
        .ok_or_else(|| format!("`{pred}` has no argument list"))?;
    if !pred.ends_with(')') {
        return Err(format!("`{pred}`: the argument list is not closed"));
    }
    let name = pred[..open].trim().to_lowercase();
    let inner = &pred[open + 1..pred.len() - 1];
    let mut args = vec![];
    let (mut depth_p, mut from) = (0usize, 0usize);
    for (i, c) in inner.char_indices() {
        match c {
            '(' => depth_p += 1,
            ')' => depth_p = depth_p.saturating_sub(1),
            ',' if depth_p == 0 => {
                args.push(parse_crd(&inner[from..i], depth + 1)?);
                from = i + 1;
            }
            _ => {}
        }
    }
    if !inner[from..].trim().is_empty() {
        args.push(parse_crd(&inner[from..], depth + 1)?);
    }
    Ok(Crd {
        noun: noun.trim().to_string(),
        relation: Some((name, args)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stage2_formulas() {
        let e = parse_stage2("G ( !near[sofa] ) & F near[chair::isbetween(sofa,table)]").unwrap();
        assert_eq!(e.predicates.len(), 2);
        assert_eq!(
            e.predicates[1].1.to_string(),
            "chair::isbetween(sofa,table)"
        );
        let e = parse_stage2("F ( near[sink] & F near[sink] )").unwrap();
        assert_eq!(e.predicates.len(), 1);
        assert!(parse_stage2("F sink").unwrap_err().contains("no complete"));
        assert!(
            parse_stage2("F near[sink")
                .unwrap_err()
                .contains("never closed")
        );
        assert!(
            parse_stage2("F ( near[sink] & bed )")
                .unwrap_err()
                .contains("bare")
        );
        assert!(
            parse_stage2("F near[a] & [x]")
                .unwrap_err()
                .contains("bracket")
        );
        assert!(parse_crd("a::b(c::d(e::f(g::h(i::j(k)))))", 0).is_err());
    }
}
