//! The repair loop for JSON groundings (the Schema graph, catalog ids): the same policy as the
//! `.m2r` loop (`lower::repair`): up to R rounds after the first answer, certain fixes applied
//! locally before a round is spent, a planning failure ends the episode unless asked otherwise;
//! only the feedback speaks JSON pointers instead of program spans.

use super::GraphDiagnostic;
use super::feedback::apply_fixes;
use super::prompt::json_repair_messages;
use crate::lower::repair::{
    Attempt, DiagRecord, EpisodeOutcome, LocalFix, Phase, RepairOptions, Trace, call_model,
};
use crate::lower::{ChatModel, ChatRequest, Prompt};

/// What one reply came to: the output and the program that produced it, or the phase that
/// rejected it with its diagnostics.
pub type JsonVerdict<T> = Result<(T, String), (Phase, Vec<GraphDiagnostic>)>;

/// Most local fix passes per round.
const MAX_LOCAL_PASSES: usize = 4;

fn record(d: &GraphDiagnostic) -> DiagRecord {
    DiagRecord {
        code: d.diagnostic.code.id().to_string(),
        severity: if d.is_error() { "error" } else { "warning" }.to_string(),
        message: format!("{} (at `{}`)", d.diagnostic.message, d.pointer),
    }
}

/// Verifies `reply`, applying certain fixes while they help.
fn verify_with_fixes<T>(
    verify: &mut dyn FnMut(&str) -> JsonVerdict<T>,
    reply: &str,
    local: bool,
) -> (JsonVerdict<T>, Vec<LocalFix>, String) {
    let mut text = reply.to_string();
    let mut fixes = Vec::new();
    let mut verdict = verify(&text);
    for _ in 0..MAX_LOCAL_PASSES {
        let Err((_, diags)) = &verdict else { break };
        if !local {
            break;
        }
        let Some(next) = apply_fixes(&text, diags) else {
            break;
        };
        if next == text {
            break;
        }
        fixes.extend(diags.iter().filter(|d| d.is_error()).filter_map(|d| {
            d.patch.as_ref().map(|p| LocalFix {
                code: d.diagnostic.code.id().to_string(),
                message: d.diagnostic.message.clone(),
                replaced: d.pointer.clone(),
                replacement: p.to_string(),
            })
        }));
        text = next;
        verdict = verify(&text);
    }
    (verdict, fixes, text)
}

/// Runs one episode of a JSON grounding; `what` names the representation in repair prompts.
pub fn run_json_episode<M: ChatModel + ?Sized, T>(
    model: &M,
    verify: &mut dyn FnMut(&str) -> JsonVerdict<T>,
    first: &Prompt,
    episode: &str,
    opts: &RepairOptions,
    what: &str,
) -> Trace<T> {
    let mut attempts: Vec<Attempt> = Vec::new();
    let mut previous: Option<(String, Vec<GraphDiagnostic>)> = None;
    let mut last_program: Option<String> = None;
    let mut last_outcome = EpisodeOutcome::NoProgram {
        reply: "none".into(),
    };
    for round in 0..=opts.rounds {
        let custom_id = format!("{episode}/round{round}");
        let messages = match &previous {
            None => first.messages.clone(),
            Some((reply, diags)) => json_repair_messages(first, reply, diags, what),
        };
        let request = ChatRequest {
            custom_id,
            messages,
        };
        let (reply, mut attempt) =
            match call_model(model, &request, round, &mut attempts, &last_program) {
                Ok(answered) => answered,
                Err(ended) => return ended,
            };
        let text = reply.content.clone().unwrap_or_default();
        attempt.reply = if reply.choices == 0 {
            "empty_choice"
        } else if reply.finish_reason.as_deref() == Some("length") {
            "cut_off"
        } else {
            "json"
        }
        .into();
        attempt.program = Some(text.clone());
        let (verdict, fixes, fixed) = verify_with_fixes(verify, &text, opts.local_fixes);
        if !fixes.is_empty() {
            attempt.fixed_program = Some(fixed.clone());
        }
        attempt.local_fixes = fixes;
        match verdict {
            Ok((output, program)) => {
                attempt.outcome = "accepted".into();
                attempts.push(attempt);
                return Trace {
                    attempts,
                    outcome: EpisodeOutcome::Success { round },
                    output: Some(output),
                    final_program: Some(program),
                };
            }
            Err((phase, diags)) => {
                attempt.diagnostics = diags.iter().map(record).collect();
                attempt.outcome = match phase {
                    Phase::Check => "rejected_check",
                    Phase::Ground => "rejected_ground",
                    Phase::Verify => "rejected_verify",
                    Phase::Plan => "plan_failed",
                }
                .into();
                attempts.push(attempt);
                last_program = Some(fixed.clone());
                if phase == Phase::Plan {
                    last_outcome = EpisodeOutcome::PlanFailed;
                    if !opts.repair_on_plan_failure {
                        break;
                    }
                } else {
                    last_outcome = EpisodeOutcome::Rejected { phase };
                }
                previous = Some((fixed, diags));
            }
        }
    }
    Trace {
        attempts,
        outcome: last_outcome,
        output: None,
        final_program: last_program,
    }
}
