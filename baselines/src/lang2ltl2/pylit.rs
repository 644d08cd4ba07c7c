//! A small reader of Python literals (strings in single or double quotes, lists, dicts, numbers,
//! `True`/`False`/`None`), the syntax Lang2LTL-2's recogniser answers in, into JSON values.
//! Bounded in depth and length, so a hostile reply is an error, never a crash.

use serde_json::{Map, Value};

const MAX_DEPTH: usize = 32;

pub fn parse(text: &str) -> Result<Value, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut p = Parser { s: &chars, i: 0 };
    let v = p.value(0)?;
    p.ws();
    if p.i != chars.len() {
        return Err(format!("unexpected `{}` after the value", chars[p.i]));
    }
    Ok(v)
}

struct Parser<'a> {
    s: &'a [char],
    i: usize,
}

impl Parser<'_> {
    fn ws(&mut self) {
        while self.s.get(self.i).is_some_and(|c| c.is_whitespace()) {
            self.i += 1;
        }
    }

    fn value(&mut self, depth: usize) -> Result<Value, String> {
        if depth > MAX_DEPTH {
            return Err("the value nests too deep".into());
        }
        self.ws();
        match self.s.get(self.i) {
            None => Err("the value ends early".into()),
            Some('\'') | Some('"') => self.string().map(Value::String),
            Some('[') | Some('(') => {
                let close = if self.s[self.i] == '[' { ']' } else { ')' };
                self.i += 1;
                let mut out = vec![];
                loop {
                    self.ws();
                    if self.s.get(self.i) == Some(&close) {
                        self.i += 1;
                        return Ok(Value::Array(out));
                    }
                    out.push(self.value(depth + 1)?);
                    self.ws();
                    match self.s.get(self.i) {
                        Some(',') => self.i += 1,
                        Some(c) if *c == close => {}
                        _ => return Err(format!("a list is not closed with `{close}`")),
                    }
                }
            }
            Some('{') => {
                self.i += 1;
                let mut out = Map::new();
                loop {
                    self.ws();
                    if self.s.get(self.i) == Some(&'}') {
                        self.i += 1;
                        return Ok(Value::Object(out));
                    }
                    let k = match self.value(depth + 1)? {
                        Value::String(s) => s,
                        other => other.to_string(),
                    };
                    self.ws();
                    if self.s.get(self.i) != Some(&':') {
                        return Err("a dict key is not followed by `:`".into());
                    }
                    self.i += 1;
                    let v = self.value(depth + 1)?;
                    out.insert(k, v);
                    self.ws();
                    match self.s.get(self.i) {
                        Some(',') => self.i += 1,
                        Some('}') => {}
                        _ => return Err("a dict is not closed with `}`".into()),
                    }
                }
            }
            Some(_) => {
                let start = self.i;
                while self
                    .s
                    .get(self.i)
                    .is_some_and(|c| c.is_alphanumeric() || matches!(c, '_' | '.' | '-' | '+'))
                {
                    self.i += 1;
                }
                let word: String = self.s[start..self.i].iter().collect();
                match word.as_str() {
                    "" => Err(format!("unexpected `{}`", self.s[self.i])),
                    "True" | "true" => Ok(Value::Bool(true)),
                    "False" | "false" => Ok(Value::Bool(false)),
                    "None" | "null" => Ok(Value::Null),
                    w => w
                        .parse::<f64>()
                        .ok()
                        .and_then(|f| serde_json::Number::from_f64(f).map(Value::Number))
                        .ok_or_else(|| format!("`{w}` is not a literal")),
                }
            }
        }
    }

    fn string(&mut self) -> Result<String, String> {
        let q = self.s[self.i];
        self.i += 1;
        let mut out = String::new();
        while let Some(&c) = self.s.get(self.i) {
            self.i += 1;
            match c {
                '\\' => {
                    let e = *self.s.get(self.i).ok_or("a string ends in `\\`")?;
                    self.i += 1;
                    out.push(match e {
                        'n' => '\n',
                        't' => '\t',
                        other => other,
                    });
                }
                c if c == q => return Ok(out),
                c => out.push(c),
            }
        }
        Err("a string is not closed".into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn python_literals() {
        assert_eq!(parse("['a', \"b's\"]").unwrap(), json!(["a", "b's"]));
        assert_eq!(
            parse("[{'left of': ['the lamp', 'the bed']}]").unwrap(),
            json!([{"left of": ["the lamp", "the bed"]}])
        );
        assert!(parse("['a'").is_err());
        assert!(parse(&"[".repeat(100)).is_err());
    }
}
