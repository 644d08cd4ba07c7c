//! `oracle` and `hard-only`: the episode's gold `.m2r` program compiled and planned by m2rc.
//! `hard-only` first removes every `prefer` constraint from the program (through the AST, so
//! any program the parser accepts can be stripped, not only generated ones).

use super::{Method, MethodError, Prediction, PreparedMap, start_cell};
use crate::episode::Episode;
use crate::pipeline::{PipelineOptions, compile_and_plan_with};
use m2rc_grammar::ast::{ConstraintKind, Item, Program, RouteItem, StageItem};
use m2rc_stdlib::grid::Cell;

pub struct Oracle {
    /// Keep the soft preferences (`oracle`) or drop them (`hard-only`).
    pub soft: bool,
}

impl Method for Oracle {
    fn name(&self) -> &str {
        if self.soft { "oracle" } else { "hard-only" }
    }

    fn config(&self) -> serde_json::Value {
        serde_json::json!({
            "method": self.name(),
            "m2rc": env!("CARGO_PKG_VERSION"),
            "preferences": self.soft,
            "planner": "sequential",
        })
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let gold = episode.m2rc_gold_program.as_deref().ok_or_else(|| {
            MethodError("the episode has no gold program (`m2rc_gold_program`)".into())
        })?;
        let program = if self.soft {
            gold.to_string()
        } else {
            strip_preferences(gold)?
        };
        let start = start_cell(&map.map, episode)?;
        let trajectory = plan(&program, map, start)?;
        Ok(Prediction {
            trajectory,
            program: Some(program),
            notes: vec![],
            ..Prediction::default()
        })
    }
}

/// Compiles and plans `program` from `start` with the default pipeline (sequential planner,
/// default cost profile); any diagnostic that stops compilation becomes the method error.
fn plan(program: &str, map: &PreparedMap, start: Cell) -> Result<Vec<Cell>, MethodError> {
    let opts = PipelineOptions {
        start: Some(start),
        ..PipelineOptions::default()
    };
    match compile_and_plan_with(program, &map.map, map.planning()?, &opts) {
        Ok(compiled) => Ok(compiled.route.trajectory),
        Err(diags) => {
            let first = diags.iter().find(|d| d.is_error()).or(diags.first());
            Err(MethodError(match first {
                Some(d) => format!("gold program does not compile: {} {}", d.code, d.message),
                None => "gold program does not compile".to_string(),
            }))
        }
    }
}

/// The program without its `prefer` constraints, pretty-printed.
pub fn strip_preferences(source: &str) -> Result<String, MethodError> {
    let parsed = m2rc_grammar::parse(source);
    if let Some(e) = parsed.errors.first() {
        return Err(MethodError(format!("gold program does not parse: {e:?}")));
    }
    let mut program: Program = parsed.program;
    for item in &mut program.items {
        if let Item::Route(route) = item {
            strip_route_items(&mut route.items);
        }
    }
    Ok(m2rc_grammar::print(&program))
}

fn strip_route_items(items: &mut Vec<RouteItem>) {
    items.retain(|i| !matches!(i, RouteItem::Constraint(c) if c.kind == ConstraintKind::Prefer));
    for item in items.iter_mut() {
        match item {
            RouteItem::Stage(stage) => {
                stage.body.retain(
                    |b| !matches!(b, StageItem::Constraint(c) if c.kind == ConstraintKind::Prefer),
                );
            }
            RouteItem::For(f) => strip_route_items(&mut f.body),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn preferences_are_removed_everywhere_and_nothing_else() {
        let src = "let t1 = objects(bed).only()\nroute {\n  go t1 {\n    avoid rooms(kitchen).only()\n    prefer near(objects(sofa).only()) within t1.room()\n  }\n  prefer clearance(0.5m)\n  avoid rooms(bathroom).only()\n}\n";
        let out = strip_preferences(src).unwrap();
        assert!(!out.contains("prefer"), "{out}");
        assert!(out.contains("avoid rooms(kitchen).only()"), "{out}");
        assert!(out.contains("avoid rooms(bathroom).only()"), "{out}");
        assert!(out.contains("go t1"), "{out}");
    }
}
