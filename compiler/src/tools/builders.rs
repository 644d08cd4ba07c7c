//! The RouteIR builders of a session: the segment context, constraints, segments and the task
//! that puts them together as an intent graph and checks it with the compiler.

use super::{
    Finished, Handle, Outcome, Stored, ToolSession, clip, describe, graph_program, is_name, short,
};
use crate::check::check;
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;

impl ToolSession<'_> {
    fn builder_handle(&mut self, kind: &str, stored: Stored, text: String) -> Outcome {
        let name = format!("{kind}#{}", self.handles.len() + 1);
        self.handles.push(Handle {
            name: name.clone(),
            stored,
        });
        Ok(json!({"handle": name, "value": format!("{name}: {text}")}))
    }

    fn segment_id(v: Option<&Value>) -> Result<Option<String>, String> {
        match v {
            None | Some(Value::Null) => Ok(None),
            Some(Value::String(s)) if is_name(s) => Ok(Some(s.clone())),
            Some(other) => Err(format!(
                "a segment id is a name (`s1`), not {}",
                clip(&other.to_string())
            )),
        }
    }

    pub(super) fn build(&mut self, name: &str, args: &Map<String, Value>) -> Outcome {
        match name {
            "set_segment_context" => {
                let id = Self::segment_id(args.get("segment_id"))?
                    .ok_or("`set_segment_context` needs `segment_id`")?;
                self.context = Some(id.clone());
                Ok(json!({"context": id, "value": format!(
                    "constraints made from now on belong to segment `{id}` unless they name segments"
                )}))
            }
            "constraint" => {
                let kind = args.get("kind").and_then(Value::as_str).unwrap_or("");
                let field = match kind {
                    "require_visit" | "forbid" => "place",
                    "prefer" => "preference",
                    _ => {
                        return Err(format!(
                            "a constraint's `kind` is require_visit, forbid or prefer, not `{}`",
                            clip(kind)
                        ));
                    }
                };
                let value = self.resolve(args.get("value").unwrap_or(&Value::Null))?;
                let mut graph = json!({"kind": kind, field: value});
                let mut text = format!("{kind} {}", short(args.get("value")));
                if let Some(w) = args.get("within") {
                    graph["within"] = self.resolve(w)?;
                    text.push_str(&format!(" within {}", short(Some(w))));
                }
                let during = match args.get("segments") {
                    Some(Value::Array(a)) => Some(
                        a.iter()
                            .map(|x| {
                                Self::segment_id(Some(x))?.ok_or("a segment id is a name".into())
                            })
                            .collect::<Result<Vec<_>, String>>()?,
                    ),
                    Some(_) => return Err("`segments` is a list of segment ids".into()),
                    None => self.context.clone().map(|c| vec![c]),
                };
                if let Some(d) = &during {
                    text.push_str(&format!(" during {}", d.join(", ")));
                }
                self.builder_handle("constraint", Stored::Constraint { graph, during }, text)
            }
            "segment" => {
                let id = Self::segment_id(args.get("segment_id"))?;
                let target = self.resolve(args.get("target").unwrap_or(&Value::Null))?;
                let constraints = self.builder_list(args.get("constraints"), "constraint")?;
                let text = format!(
                    "go to {}{} with {} constraint(s)",
                    short(args.get("target")),
                    id.as_ref()
                        .map(|i| format!(" as `{i}`"))
                        .unwrap_or_default(),
                    constraints.len()
                );
                self.builder_handle(
                    "segment",
                    Stored::Segment {
                        id,
                        target,
                        constraints,
                    },
                    text,
                )
            }
            "task" => self.task(args),
            _ => Err(format!("no builder `{name}`")),
        }
    }

    /// Indices of the handles of a list argument, each of the wanted builder kind.
    fn builder_list(&self, v: Option<&Value>, want: &str) -> Result<Vec<usize>, String> {
        let items = match v {
            None | Some(Value::Null) => return Ok(Vec::new()),
            Some(Value::Array(a)) => a,
            Some(_) => return Err(format!("a list of {want} handles was expected")),
        };
        items
            .iter()
            .map(|x| {
                let s = x.as_str().unwrap_or("");
                match self.handle(s) {
                    Some((i, h)) => match (&h.stored, want) {
                        (Stored::Constraint { .. }, "constraint")
                        | (Stored::Segment { .. }, "segment") => Ok(i),
                        _ => Err(format!("`{s}` is not a {want} handle")),
                    },
                    None => Err(format!("there is no {want} handle `{}`", clip(s))),
                }
            })
            .collect()
    }

    /// Puts the route together and checks it: the submitted graph and program, or the
    /// compiler's errors (the model may fix them and call `task` again).
    fn task(&mut self, args: &Map<String, Value>) -> Outcome {
        let segs = self.builder_list(args.get("segments"), "segment")?;
        if segs.is_empty() {
            return Err("`task` needs at least one segment handle".into());
        }
        let listed_route = self.builder_list(args.get("constraints"), "constraint")?;
        let mut placed: Vec<usize> = listed_route.clone();
        for &s in &segs {
            if let Stored::Segment { constraints, .. } = &self.handles[s].stored {
                placed.extend(constraints);
            }
        }
        let ids: Vec<Option<String>> = segs
            .iter()
            .map(|&s| match &self.handles[s].stored {
                Stored::Segment { id, .. } => id.clone(),
                _ => None,
            })
            .collect();
        // Constraints listed nowhere go to their one segment, else to the route with their scope.
        let mut extra_body: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        let mut extra_route: Vec<usize> = Vec::new();
        for (i, h) in self.handles.iter().enumerate() {
            if let Stored::Constraint { during, .. } = &h.stored
                && !placed.contains(&i)
            {
                let home = during
                    .as_ref()
                    .filter(|d| d.len() == 1)
                    .and_then(|d| ids.iter().position(|id| id.as_deref() == Some(&d[0])));
                match home {
                    Some(k) => extra_body.entry(k).or_default().push(i),
                    None => extra_route.push(i),
                }
            }
        }
        let body_graph = |i: usize| match &self.handles[i].stored {
            Stored::Constraint { graph, .. } => graph.clone(),
            _ => Value::Null,
        };
        let route_graph = |i: usize| match &self.handles[i].stored {
            Stored::Constraint { graph, during } => {
                let mut g = graph.clone();
                if let Some(d) = during {
                    g["during"] = json!(d);
                }
                g
            }
            _ => Value::Null,
        };
        let mut segments = Vec::new();
        for (k, &s) in segs.iter().enumerate() {
            let Stored::Segment {
                id,
                target,
                constraints,
            } = &self.handles[s].stored
            else {
                continue;
            };
            let mut o = Map::new();
            if let Some(id) = id {
                o.insert("id".into(), json!(id));
            }
            o.insert("to".into(), target.clone());
            let cons: Vec<Value> = constraints
                .iter()
                .chain(extra_body.get(&k).into_iter().flatten())
                .map(|&i| body_graph(i))
                .collect();
            if !cons.is_empty() {
                o.insert("constraints".into(), Value::Array(cons));
            }
            segments.push(Value::Object(o));
        }
        let mut graph = json!({"segments": segments});
        let route: Vec<Value> = listed_route
            .iter()
            .chain(&extra_route)
            .map(|&i| route_graph(i))
            .collect();
        if !route.is_empty() {
            graph["constraints"] = Value::Array(route);
        }
        let program = graph_program(&graph)?;
        let checked = check(&program, &self.vocab);
        let errors: Vec<String> = checked.errors().map(describe).collect();
        if !errors.is_empty() {
            return Err(format!("the route does not compile: {}", errors.join("; ")));
        }
        let n = segments_len(&graph);
        self.finished = Some(Finished { graph, program });
        Ok(json!({"submitted": true, "value": format!("a route of {n} segment(s) was submitted")}))
    }
}

fn segments_len(graph: &Value) -> usize {
    graph["segments"].as_array().map_or(0, Vec::len)
}
