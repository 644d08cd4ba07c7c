//! `m2rc ltl <formula>`: an LTLf formula to its minimal automaton, without a program or a map
//! (for checking the backend against other tools; `scripts/ltl-crosscheck.sh` uses it).

use crate::io::unusable;
use anyhow::Result;
use clap::{Args, ValueEnum};
use m2rc_compiler::diagnostic::render_text;
use m2rc_compiler::ltl::budget::Budget;
use m2rc_compiler::ltl::dfa::build_with;
use m2rc_compiler::ltl::syntax::Kind;
use m2rc_compiler::ltl::{AtomKind, Dfa, check_formula, export, parse};
use std::process::ExitCode;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LtlEmit {
    /// The formula as m2rc prints it.
    Ltl,
    /// The minimal automaton as JSON.
    Dfa,
    Hoa,
    Dot,
}

#[derive(Args)]
pub struct LtlArgs {
    /// The formula, e.g. `F(a & F b) & G !c`.
    pub formula: String,
    /// Output format: the automaton as JSON (`dfa`), HOA, Graphviz DOT, or the formula (`ltl`).
    #[arg(long, value_enum, default_value_t = LtlEmit::Dfa)]
    pub emit: LtlEmit,
    /// Atom order (comma-separated, each an atom name of the formula syntax, each once); default:
    /// first occurrence in the formula.
    #[arg(long, value_delimiter = ',')]
    pub atoms: Vec<String>,
    /// Keep the automaton as progression builds it (for comparing with the minimised one).
    #[arg(long)]
    pub no_minimise: bool,
    /// Build the automaton this many times and print the mean construction time to stderr.
    #[arg(long)]
    pub bench: Option<u32>,
}

/// Refuses an `--atoms` list the outputs could not name unambiguously: a name listed twice would
/// be two HOA `AP`s and two JSON atoms with one name, and a name that is not an atom of the
/// syntax (empty, an operator, `a-b`) would print guards that do not parse back.
fn check_atom_list(atoms: &[String]) -> Result<()> {
    for (k, a) in atoms.iter().enumerate() {
        if a.is_empty() {
            return Err(unusable(anyhow::anyhow!(
                "--atoms: name {} of the list is empty",
                k + 1
            )));
        }
        if !matches!(parse(a).map(|f| f.kind), Ok(Kind::Atom(n)) if n == *a) {
            return Err(unusable(anyhow::anyhow!(
                "--atoms: `{a}` is not an atom name: atoms are identifiers (ASCII letters, digits \
                 and `_`, not starting with a digit) other than the operators and constants of \
                 the syntax"
            )));
        }
        if atoms[..k].contains(a) {
            return Err(unusable(anyhow::anyhow!("--atoms lists `{a}` twice")));
        }
    }
    Ok(())
}

pub fn run(a: LtlArgs) -> Result<ExitCode> {
    check_atom_list(&a.atoms)?;
    let checked = match check_formula(&a.formula, 0, &|_| AtomKind::Place, &[]) {
        Ok(c) => c,
        // An unsatisfiable formula still has an automaton (it accepts nothing); print it.
        Err(d) if d.iter().all(|x| x.code.id() == "E0807") => {
            eprint!("{}", render_text(&d, "<formula>", &a.formula));
            let f =
                m2rc_compiler::ltl::parse(&a.formula).map_err(|e| anyhow::anyhow!(e.message))?;
            let atoms: Vec<String> = f.atoms().into_iter().map(String::from).collect();
            let dfa = Dfa::build(&f, &atoms, true).map_err(|e| anyhow::anyhow!(e.to_string()))?;
            return emit(&a, &f, dfa);
        }
        Err(d) => {
            eprint!("{}", render_text(&d, "<formula>", &a.formula));
            return Ok(ExitCode::FAILURE);
        }
    };
    let mut atoms = checked.atoms.clone();
    if !a.atoms.is_empty() {
        if let Some(missing) = atoms.iter().find(|x| !a.atoms.contains(x)) {
            return Err(unusable(anyhow::anyhow!(
                "--atoms does not list `{missing}`, an atom of the formula"
            )));
        }
        atoms = a.atoms.clone();
    }
    let dfa = Dfa::build(&checked.formula, &atoms, !a.no_minimise)
        .map_err(|e| anyhow::anyhow!(e.to_string()))?;
    if let Some(k) = a.bench.filter(|k| *k > 0) {
        let t = std::time::Instant::now();
        let mut steps = 0;
        for _ in 0..k {
            let mut budget = Budget::default();
            let d = build_with(&checked.formula, &atoms, !a.no_minimise, &mut budget)
                .map_err(|e| anyhow::anyhow!(e.to_string()))?;
            steps = budget.used();
            std::hint::black_box(d);
        }
        eprintln!(
            "{} atoms, {} states, {steps} construction steps of {}: {:.3} ms per construction (mean of {k})",
            atoms.len(),
            dfa.states(),
            m2rc_compiler::ltl::budget::MAX_WORK,
            t.elapsed().as_secs_f64() * 1e3 / k as f64
        );
    }
    emit(&a, &checked.formula, dfa)
}

fn emit(a: &LtlArgs, f: &m2rc_compiler::ltl::Formula, dfa: Dfa) -> Result<ExitCode> {
    match a.emit {
        LtlEmit::Ltl => println!("{f}"),
        LtlEmit::Dfa => println!("{}", serde_json::to_string_pretty(&export::to_json(&dfa))?),
        LtlEmit::Hoa => print!("{}", export::to_hoa(&dfa, &f.to_string())),
        LtlEmit::Dot => print!("{}", export::to_dot(&dfa, "ltl")),
    }
    Ok(ExitCode::SUCCESS)
}
