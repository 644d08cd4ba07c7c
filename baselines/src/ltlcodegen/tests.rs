//! The sandbox's subset, budgets and refusals; the attempt loop; the label map and the planner on
//! the demo house.

use super::sandbox::{MAX_FORMULA_NODES, MAX_SOURCE_BYTES, MAX_STEPS, run};
use super::*;

fn any(_: &str) -> bool {
    true
}

fn formula(src: &str) -> String {
    run(src, &any)
        .map(|e| e.formula.to_string())
        .unwrap_or_else(|e| format!("ERROR {e}"))
}

#[test]
fn the_subset_builds_formulas_across_lines_with_comments_and_docstrings() {
    let src = r#"
# the model's code
def question():
    """Go to the sofa, then the bed; never the kitchen."""
    sofa = ap("object_3")  # first sofa
    bed = ap('object_9')
    kitchen = ap("room_2")
    return ltl_and(
        ltl_eventually(ltl_and(sofa, ltl_eventually(bed))),
        ltl_always(ltl_not(kitchen)),
    )
    this_is_never_run = ap("object_404")
"#;
    assert_eq!(formula(src), "F(object_3 & F object_9) & G !room_2");
    let e = run(src, &any).unwrap();
    assert_eq!(e.aps, ["object_3", "object_9", "room_2"]);
    // Lists are spread by ltl_and / ltl_or; until and imply take two.
    let src = "def question():\n    xs = [ap(\"a\"), ap(\"b\")]\n    return ltl_or(xs, ltl_until(ap(\"c\"), ltl_imply(ap(\"a\"), ap(\"b\"))))\n";
    assert_eq!(formula(src), "a | b | c U (a -> b)");
}

#[test]
fn constructs_outside_the_subset_are_refused_with_their_line() {
    let cases = [
        (
            "import os\ndef question():\n    return ap(\"a\")\n",
            1,
            "imports",
        ),
        (
            "def question():\n    for x in range(3):\n        pass\n    return ap(\"a\")\n",
            2,
            "`for`",
        ),
        (
            "def question():\n    if True:\n        return ap(\"a\")\n",
            2,
            "`if`",
        ),
        (
            "def question():\n    return ap(\"a\").__class__\n",
            2,
            "attribute",
        ),
        (
            "def question():\n    return open(\"/etc/passwd\")\n",
            2,
            "not a function of the operator library",
        ),
        (
            "def question():\n    return ap(\"a\") & ap(\"b\")\n",
            2,
            "operator `&`",
        ),
        (
            "def question():\n    return ltl_eventually(x=ap(\"a\"))\n",
            2,
            "keyword",
        ),
        (
            "def question():\n    return ap(\"a\")\nprint(question())\n",
            3,
            "outside question()",
        ),
        (
            "def helper():\n    return ap(\"a\")\n",
            1,
            "must be `question`",
        ),
        (
            "def question():\n    return ltl_until(ap(\"a\"))\n",
            2,
            "takes 2",
        ),
        (
            "def question():\n    return ltl_not(\"a\")\n",
            2,
            "takes formulas",
        ),
        ("def question():\n    return undefined\n", 2, "not defined"),
        ("def question():\n    x = ap(\"a\")\n", 0, "does not return"),
        ("def question():\n    return ap(\"a\n", 2, "unterminated"),
        ("", 0, "empty"),
    ];
    for (src, line, why) in cases {
        let e = run(src, &any).unwrap_err();
        assert!(e.message.contains(why), "{src:?}: {e}");
        assert_eq!(e.line, line, "{src:?}: {e}");
    }
    let e = run("def question():\n    return ap(\"object_7\")\n", &|a| {
        a != "object_7"
    })
    .unwrap_err();
    assert!(e.message.contains("not an AP of the inventory"), "{e}");
}

#[test]
fn the_budgets_stop_doubling_long_and_deep_programs() {
    // Thirty doublings would be a formula of a billion nodes.
    let mut src = String::from("def question():\n    f = ap(\"a\")\n");
    for _ in 0..30 {
        src.push_str("    f = ltl_and(f, f)\n");
    }
    src.push_str("    return f\n");
    let e = run(&src, &any).unwrap_err();
    assert!(
        e.message
            .contains(&format!("past {MAX_FORMULA_NODES} nodes")),
        "{e}"
    );
    // Many cheap statements: the step budget.
    let mut src = String::from("def question():\n");
    for _ in 0..MAX_STEPS {
        src.push_str("    x=ap('a')\n");
    }
    src.push_str("    return x\n");
    let e = run(&src, &any).unwrap_err();
    assert!(
        e.message.contains("bytes") || e.message.contains("steps") || e.message.contains("tokens"),
        "{e}"
    );
    let long = "#".repeat(MAX_SOURCE_BYTES + 1);
    assert!(run(&long, &any).unwrap_err().message.contains("bytes"));
    let deep = format!(
        "def question():\n    return {}ap(\"a\"){}\n",
        "ltl_not(".repeat(100),
        ")".repeat(100)
    );
    assert!(run(&deep, &any).unwrap_err().message.contains("deeper"));
}

#[test]
fn top_level_ap_conjuncts_are_removed_as_start_preconditions() {
    let e = run(
        "def question():\n    return ltl_and(ap(\"room_1\"), ltl_and(ltl_eventually(ap(\"b\")), ap(\"c\")))\n",
        &any,
    )
    .unwrap();
    let (f, removed) = strip_initial_aps(e.formula);
    assert_eq!(f.to_string(), "F b");
    assert_eq!(removed, ["room_1", "c"]);
}

struct Script(Vec<Result<String, CallError>>, Vec<(String, String)>);

impl Ask for Script {
    fn ask(&mut self, call: &str, _system: &str, user: &str) -> Result<String, CallError> {
        self.1.push((call.to_string(), user.to_string()));
        if self.0.is_empty() {
            return Err(CallError::Failed("no more replies".into()));
        }
        self.0.remove(0)
    }
}

fn demo() -> (SemanticMap, Inventory, Vec<bool>, Cell) {
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let n = map.n();
    let trav: Vec<bool> = (0..n * n)
        .map(|i| map.is_free(Cell::new((i / n) as u32, (i % n) as u32)))
        .collect();
    let start = map.start.unwrap_or_else(|| {
        let i = trav.iter().position(|&t| t).unwrap();
        Cell::new((i / n) as u32, (i % n) as u32)
    });
    let inv = Inventory::build(&map);
    (map, inv, trav, start)
}

#[test]
fn a_failed_attempt_is_retried_with_its_code_and_error_and_the_third_plans_a_route() {
    let (map, inv, trav, start) = demo();
    let room = inv.rooms.last().unwrap().0.clone();
    let good =
        format!("```python\ndef question():\n    return ltl_eventually(ap(\"{room}\"))\n```");
    let mut s = Script(
        vec![
            Ok("Sure! Here is the code.".into()),
            Ok("def question():\n    return ap(\"object_999999\")\n".into()),
            Ok(good),
        ],
        vec![],
    );
    let out = run_episode(&map, &inv, &trav, "go to the room", start, &mut s);
    assert_eq!(out.status, "ok", "{}", out.record);
    let calls: Vec<&str> = s.1.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(calls, CALLS);
    assert!(
        s.1[1].1.contains("Sure! Here is the code.")
            && s.1[1].1.contains("expected `def question():`")
    );
    assert!(s.1[2].1.contains("object_999999") && s.1[2].1.contains("not an AP of the inventory"));
    assert!(!s.1[0].1.contains("Previous code"));
    let id: u32 = room.trim_start_matches("room_").parse().unwrap();
    assert_eq!(map.room_at(*out.trajectory.last().unwrap()), id);
    assert_eq!(out.record["attempts"].as_array().unwrap().len(), 3);
    // Three failures, or a refused call: start only.
    let mut s = Script(vec![Ok("x".into()), Ok("y".into()), Ok("z".into())], vec![]);
    let out = run_episode(&map, &inv, &trav, "go", start, &mut s);
    assert_eq!(
        (out.status.as_str(), out.trajectory.clone()),
        ("codegen_failed", vec![start])
    );
    let mut s = Script(
        vec![Err(CallError::Failed("HTTP 403: refused".into()))],
        vec![],
    );
    let out = run_episode(&map, &inv, &trav, "go", start, &mut s);
    assert_eq!(out.status, "codegen_failed");
    assert!(out.record.to_string().contains("refused"));
}

#[test]
fn object_aps_label_the_free_cells_within_a_metre_of_the_centre() {
    let (map, inv, trav, _) = demo();
    let n = map.n();
    let o = map
        .objects
        .iter()
        .find(|o| !o.footprint.is_empty())
        .unwrap();
    let cells = inventory::label_cells(&map, &inv, &format!("object_{}", o.id));
    assert!(!cells.is_empty());
    for &i in &cells {
        let (r, c) = ((i as usize / n) as f64, (i as usize % n) as f64);
        assert!(trav[i as usize]);
        if cells.len() > 1 {
            assert!((r - o.center[0]).hypot(c - o.center[1]) <= 20.0);
        }
    }
    assert!(inventory::label_cells(&map, &inv, "object_99999999").is_empty());
}
