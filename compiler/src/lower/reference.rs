//! The language reference the model reads: the rules it must know, then every built-in of
//! `stdlib::builtins` (one line each, generated from the table, so a new row appears in the
//! prompt the moment it is added).

use m2rc_stdlib::builtins;

/// The rules of `.m2r` that a model gets wrong without being told, in the order it needs them.
pub const RULES: &str = "\
Rules of .m2r:
- A program is `let` bindings followed by one `route { ... }` block. Comments start with `//`.
- Categories are written bare and only the categories listed in the scene catalog exist:
  `objects(chair)`, `rooms(bedroom)`, `objects(sofa | arm_chair)` (a union). Never quote them.
- Sets and single things are different types. `objects(chair)` is a Set<Object>; a place slot
  (`area_between`, `.room()`, ...) needs one Object, Room or Region; `go`/`pass` on a set mean
  any one of them (for \"a box\", \"any toilet\"). For \"the chair\" choose one
  explicitly: `.nearest(x)`, `.farthest(x)`, `.kth_nearest(k, x)`, `.largest()`, `.smallest()`,
  `.max_by(r => ...)`, `.min_by(o => ...)`, or `.only()` when the instruction implies exactly one.
  A singular noun is not proof of uniqueness: prefer a ranking when the instruction gives one.
- Filters narrow a set (`.in(room)`, `.near(x)`, `.on(x)`, `.next_to(x)`, `.where(o => ...)`);
  the same words on one thing are predicates (Bool) for `.where` and `if`.
- `if` is an expression that chooses a value, never a statement around stages: \"go to the lamp
  if there is one, else the desk\" is `go if lamps.exists() { lamps.nearest() } else { desk }`.
- Stages: each `go <place>` is one stage, visited in the order written. Constraints inside a
  stage body `go x { ... }` hold only while heading to x. Constraints after the stages in the
  route block hold for the whole route, or only `during` the named stages (`go x as name`).
- `pass <place>` (must pass, in order, inside a stage), `avoid <place or set>` (never enter) are
  hard; `prefer near(x)`, `far(x)`, `closer(a, b)`, `circle(x, dir)`, `follow_wall(room, dir)`,
  `patrol(room, dir)`, `clearance(d)` are soft.
- `within <place>` restricts a constraint to an area (\"while in the kitchen\" -> `within kitchen`).
- `start` is the start position; `here` is where the current stage starts.
- Units: lengths are written with a unit, `1.5m` or `30cm`; there are no coordinates or cells.
  Areas are in square metres (`r.area()`); counts are Int (`objects(window).in(r).count() == 2`).
- Route-dependent places (`room_before_entering(r)`, `doorway_leaving(r)`, `doorway_entering(r)`,
  `first_entered(rooms)`) are bound against the planned route by the compiler.
- Keep every clause of the instruction: each destination is a stage, each \"avoid\"/\"do not pass\"
  is an `avoid`, each \"stay close/away\" is a `prefer`, with the scope the instruction gives.
";

/// The built-in functions, constants and words, one per line: `signature  // doc`.
pub fn builtins_reference() -> String {
    builtins::prompt_reference()
}

/// The whole reference section of the prompt.
pub fn language_reference() -> String {
    format!(
        "{RULES}\nBuilt-in functions, constants and words (`Set<T>.f(...)` is a method on sets; \
`x: T = v` has a default; any argument may be passed by name, `by: travel`):\n{}",
        builtins_reference()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_row_appears_in_the_reference() {
        let text = language_reference();
        for b in builtins::BUILTINS {
            assert!(
                text.contains(&b.signature(None)),
                "missing {}",
                b.signature(None)
            );
        }
        for c in builtins::CONSTANTS {
            assert!(text.contains(&format!("{}: {}", c.name, c.ty)));
        }
        assert!(text.contains("Sets and single things"));
    }
}
