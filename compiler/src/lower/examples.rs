//! Worked examples for the prompt: real instructions of the Map2Route development scenes with the
//! programs that realise them, compiled into the binary from `tests/ui/real/` (where CI checks that
//! each one still compiles). An example is never taken from the scene being solved.

/// The candidate files, in the order the prompt uses them: varied constructs first (a scoped
/// preference, an avoid between two objects, a set avoided whole, two stages, a negated
/// predicate), then a hard multi-stage instruction and two more easy ones as substitutes.
const FILES: &[(&str, &str)] = &[
    (
        "108_006",
        include_str!("../../../tests/ui/real/108_006.m2r"),
    ),
    (
        "111_002",
        include_str!("../../../tests/ui/real/111_002.m2r"),
    ),
    (
        "114_002",
        include_str!("../../../tests/ui/real/114_002.m2r"),
    ),
    (
        "108_009",
        include_str!("../../../tests/ui/real/108_009.m2r"),
    ),
    (
        "111_004",
        include_str!("../../../tests/ui/real/111_004.m2r"),
    ),
    (
        "108_018",
        include_str!("../../../tests/ui/real/108_018.m2r"),
    ),
    (
        "114_001",
        include_str!("../../../tests/ui/real/114_001.m2r"),
    ),
    (
        "clause_c2_sofa_near_bedroom",
        include_str!("../../../tests/ui/real/clause_c2_sofa_near_bedroom.m2r"),
    ),
];

/// One instruction with its program.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Example {
    /// The file stem in `tests/ui/real/`.
    pub name: &'static str,
    /// The Map2Route scene the instruction was written for (`108`), when it names one.
    pub scene: Option<u32>,
    pub instruction: String,
    /// The program without its leading comment (which quotes the instruction).
    pub program: String,
}

/// Splits a `tests/ui/real` file into its quoted instruction and the program after the header.
fn parse(name: &'static str, text: &str) -> Option<Example> {
    let mut header = Vec::new();
    let mut body = Vec::new();
    let mut in_header = true;
    for line in text.lines() {
        match line.trim_start().strip_prefix("//") {
            Some(rest) if in_header => header.push(rest.trim()),
            _ => {
                in_header = false;
                body.push(line);
            }
        }
    }
    let joined = header.join(" ");
    let (a, b) = (joined.find('"')?, joined.rfind('"')?);
    if b <= a {
        return None;
    }
    let instruction = joined[a + 1..b]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let scene = joined
        .strip_prefix("Scene ")
        .and_then(|s| s.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|d| d.parse().ok());
    Some(Example {
        name,
        scene,
        instruction,
        program: body.join("\n").trim().to_string() + "\n",
    })
}

/// Every embedded example, in prompt order.
pub fn all() -> Vec<Example> {
    FILES.iter().filter_map(|(n, t)| parse(n, t)).collect()
}

/// The scene number of a map id: the leading digits of its last path component, as in the
/// Map2Route naming `procthor/108_valunseen` or `108`.
pub fn scene_number(map_id: &str) -> Option<u32> {
    let last = map_id.rsplit('/').next().unwrap_or(map_id);
    let digits: String = last.chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

/// Up to `n` examples, none from the scene of `map_id`.
///
/// Generated suites number their scenes the same way (`108_valunseen` is the 108th house of the
/// suite, not the reference's scene 108), so this may skip an example that would have been safe;
/// it never includes one that is not.
pub fn select(map_id: &str, n: usize) -> Vec<Example> {
    let solving = scene_number(map_id);
    all()
        .into_iter()
        .filter(|e| e.scene.is_none() || e.scene != solving)
        .take(n)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_file_parses_into_an_instruction_and_a_program() {
        let all = all();
        assert_eq!(all.len(), FILES.len());
        for e in &all {
            assert!(e.instruction.len() > 20, "{}: {}", e.name, e.instruction);
            assert!(e.program.contains("route {"), "{}", e.name);
            assert!(!e.program.starts_with("//"), "{}", e.name);
        }
        assert_eq!(all[0].scene, Some(108));
        assert!(all[0].instruction.starts_with("Head to the garbage can"));
        assert_eq!(all.last().unwrap().scene, None);
    }

    #[test]
    fn the_scene_being_solved_gives_no_example() {
        assert_eq!(scene_number("procthor/108_valunseen"), Some(108));
        assert_eq!(scene_number("demo"), None);
        let picked = select("procthor/108_valunseen", 5);
        assert_eq!(picked.len(), 5);
        assert!(picked.iter().all(|e| e.scene != Some(108)));
        assert_eq!(select("demo", 3).len(), 3);
    }

    #[test]
    fn examples_check_against_the_benchmark_vocabulary() {
        let vocab = m2rc_stdlib::vocab::Vocabulary::benchmark();
        for e in all() {
            let r = crate::check(&e.program, &vocab);
            assert!(!r.has_errors(), "{}: {:?}", e.name, r.diagnostics);
        }
    }
}
