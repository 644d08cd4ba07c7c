//! The repair policy: up to R repair rounds after the first answer. Each program is checked,
//! grounded and verified (by the caller's [`Verifier`], which may also plan); before a round is
//! spent on the model, the unambiguous machine-applicable fixes (a diagnostic with exactly one
//! suggestion whose edit overlaps no other) are applied locally and the program is checked again.
//! Only what remains goes back to the model. As in the paper, a planning failure ends the episode
//! unless [`RepairOptions::repair_on_plan_failure`] is set.

use super::extract::{Extracted, extract};
use super::prompt::{Feedback, Prompt, repair_messages};
use super::{ChatError, ChatModel, ChatReply, ChatRequest};
use crate::diagnostic::{Diagnostic, Suggestion};
use serde::{Deserialize, Serialize};

/// Where in the pipeline a program was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Phase {
    Check,
    Ground,
    Verify,
    Plan,
}

impl Phase {
    /// The phase a diagnostic code belongs to (`E05xx` grounding, `E06xx` verification, `E07xx`
    /// planning; everything below is checking).
    pub fn of(d: &Diagnostic) -> Phase {
        let id = d.code.id();
        match id.get(..3) {
            Some("E05") => Phase::Ground,
            Some("E06") => Phase::Verify,
            Some("E07") => Phase::Plan,
            _ => Phase::Check,
        }
    }

    /// The latest phase among the errors (what stopped the program).
    pub fn of_errors(diags: &[Diagnostic]) -> Phase {
        diags
            .iter()
            .filter(|d| d.is_error())
            .map(Phase::of)
            .max_by_key(|p| *p as u8)
            .unwrap_or(Phase::Check)
    }
}

/// What the caller's pipeline made of one program.
#[derive(Clone, Debug)]
pub enum Verdict<T> {
    Accepted(T),
    Rejected {
        phase: Phase,
        diagnostics: Vec<Diagnostic>,
    },
}

/// Checks, grounds, verifies (and possibly plans) a program.
pub trait Verifier {
    type Output;
    fn verify(&mut self, source: &str) -> Verdict<Self::Output>;
}

impl<T, F: FnMut(&str) -> Verdict<T>> Verifier for F {
    type Output = T;
    fn verify(&mut self, source: &str) -> Verdict<T> {
        self(source)
    }
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RepairOptions {
    /// Repair rounds after the first answer (R; the paper uses 3).
    pub rounds: usize,
    /// Send planning failures back to the model too (the paper does not).
    pub repair_on_plan_failure: bool,
    /// Apply unambiguous machine-applicable fixes before spending a round.
    pub local_fixes: bool,
}

impl Default for RepairOptions {
    fn default() -> Self {
        RepairOptions {
            rounds: 3,
            repair_on_plan_failure: false,
            local_fixes: true,
        }
    }
}

/// One fix applied without the model.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct LocalFix {
    pub code: String,
    pub message: String,
    /// The text replaced (empty for an insertion) and its replacement.
    pub replaced: String,
    pub replacement: String,
}

/// A diagnostic as the record keeps it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct DiagRecord {
    pub code: String,
    pub severity: String,
    pub message: String,
}

impl DiagRecord {
    fn of(d: &Diagnostic) -> Self {
        DiagRecord {
            code: d.code.id().to_string(),
            severity: if d.is_error() { "error" } else { "warning" }.to_string(),
            message: d.message.clone(),
        }
    }
}

/// One round: the request, what came back, what the compiler and the local fixes made of it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Attempt {
    /// 0 for the first answer, k for the k-th repair.
    pub round: usize,
    pub custom_id: String,
    /// `code`, `empty_choice`, `refusal`, `no_code`, `cut_off`, `pending`, `model_failed`.
    pub reply: String,
    /// The program as the model wrote it.
    pub program: Option<String>,
    pub local_fixes: Vec<LocalFix>,
    /// The program after the local fixes (only when some were applied).
    pub fixed_program: Option<String>,
    /// What remained after the local fixes (errors and warnings).
    pub diagnostics: Vec<DiagRecord>,
    /// `accepted`, `rejected_check`, `rejected_ground`, `rejected_verify`, `plan_failed`, or the
    /// reply kind when there was no program.
    pub outcome: String,
    /// `None` (`null`) when the server's figure was not a token count.
    pub prompt_tokens: Option<u64>,
    pub completion_tokens: Option<u64>,
    pub latency_ms: f64,
    /// The transport failure, for `model_failed`.
    pub error: Option<String>,
}

/// How an episode ended.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum EpisodeOutcome {
    /// A program passed in round `round`.
    Success { round: usize },
    /// Every round was spent and the last program was still rejected.
    Rejected { phase: Phase },
    /// Every round was spent and the last reply had no program.
    NoProgram { reply: String },
    /// The program was valid but could not be planned (not repaired, as in the paper).
    PlanFailed,
    /// The model could not be reached or answered (after the client's retries).
    ModelFailed { message: String },
    /// A request waits in a batch file; run again after importing the replies.
    Pending { custom_id: String },
}

impl EpisodeOutcome {
    /// The record's status word.
    pub fn status(&self) -> &'static str {
        match self {
            EpisodeOutcome::Success { .. } => "ok",
            EpisodeOutcome::Rejected { .. } => "grounding_failed",
            EpisodeOutcome::NoProgram { .. } => "no_program",
            EpisodeOutcome::PlanFailed => "plan_failed",
            EpisodeOutcome::ModelFailed { .. } => "model_failed",
            EpisodeOutcome::Pending { .. } => "pending",
        }
    }
}

/// The whole episode: every attempt, the outcome, and the accepted program's output.
#[derive(Clone, Debug)]
pub struct Trace<T> {
    pub attempts: Vec<Attempt>,
    pub outcome: EpisodeOutcome,
    pub output: Option<T>,
    /// The last program the compiler saw (after local fixes).
    pub final_program: Option<String>,
}

impl<T> Trace<T> {
    pub fn local_fix_count(&self) -> usize {
        self.attempts.iter().map(|a| a.local_fixes.len()).sum()
    }

    /// Tokens of the attempts whose counts are known (see [`Trace::unknown_usage`]).
    pub fn tokens(&self) -> (u64, u64) {
        self.attempts.iter().fold((0, 0), |(p, c), a| {
            (
                p.saturating_add(a.prompt_tokens.unwrap_or(0)),
                c.saturating_add(a.completion_tokens.unwrap_or(0)),
            )
        })
    }

    /// Attempts with a reply whose token counts are unknown (left out of [`Trace::tokens`]).
    pub fn unknown_usage(&self) -> usize {
        self.attempts
            .iter()
            .filter(|a| a.prompt_tokens.is_none() || a.completion_tokens.is_none())
            .count()
    }
}

/// The unambiguous fixes of `diags` on `source`: errors with exactly one suggestion whose span
/// fits the source and overlaps no other candidate's. `None` when there is none.
/// One model call of a repair round, with its attempt record begun (round, id, tokens,
/// latency): the reply, or the trace that ends the episode when the model gave none (a batch left
/// it pending, or the call failed). Shared by the `.m2r` and the JSON repair loops.
pub(crate) fn call_model<M: ChatModel + ?Sized, T>(
    model: &M,
    request: &ChatRequest,
    round: usize,
    attempts: &mut Vec<Attempt>,
    last_program: &Option<String>,
) -> Result<(ChatReply, Attempt), Trace<T>> {
    let mut attempt = Attempt {
        round,
        custom_id: request.custom_id.clone(),
        prompt_tokens: Some(0),
        completion_tokens: Some(0),
        ..Attempt::default()
    };
    let outcome = match model.complete(request) {
        Ok(reply) => {
            attempt.prompt_tokens = reply.usage.prompt_tokens;
            attempt.completion_tokens = reply.usage.completion_tokens;
            attempt.latency_ms = reply.latency_ms;
            return Ok((reply, attempt));
        }
        Err(ChatError::Pending(id)) => {
            attempt.reply = "pending".into();
            attempt.outcome = "pending".into();
            EpisodeOutcome::Pending { custom_id: id }
        }
        Err(ChatError::Failed(message)) => {
            attempt.reply = "model_failed".into();
            attempt.outcome = "model_failed".into();
            attempt.error = Some(message.clone());
            EpisodeOutcome::ModelFailed { message }
        }
    };
    attempts.push(attempt);
    Err(Trace {
        attempts: std::mem::take(attempts),
        outcome,
        output: None,
        final_program: last_program.clone(),
    })
}

pub fn unambiguous_fixes(source: &str, diags: &[Diagnostic]) -> Option<(String, Vec<LocalFix>)> {
    let mut cands: Vec<(&Diagnostic, &Suggestion)> = diags
        .iter()
        .filter(|d| d.is_error() && d.suggestions.len() == 1)
        .map(|d| (d, &d.suggestions[0]))
        .filter(|(_, s)| {
            s.span.start <= s.span.end
                && s.span.end <= source.len()
                && source.is_char_boundary(s.span.start)
                && source.is_char_boundary(s.span.end)
                && source[s.span.start..s.span.end] != s.replacement
        })
        .collect();
    cands.sort_by_key(|(_, s)| (s.span.start, s.span.end));
    cands.dedup_by(|a, b| a.1 == b.1);
    let overlaps = |a: &Suggestion, b: &Suggestion| {
        a.span.start < b.span.end && b.span.start < a.span.end
            || (a.span.start == b.span.start
                && (a.span.start == a.span.end || b.span.start == b.span.end))
    };
    let keep: Vec<(&Diagnostic, &Suggestion)> = cands
        .iter()
        .enumerate()
        .filter(|(i, (_, s))| {
            cands
                .iter()
                .enumerate()
                .all(|(j, (_, t))| *i == j || !overlaps(s, t))
        })
        .map(|(_, c)| *c)
        .collect();
    if keep.is_empty() {
        return None;
    }
    let mut out = String::with_capacity(source.len());
    let mut pos = 0;
    let mut fixes = Vec::new();
    for (d, s) in keep {
        out.push_str(&source[pos..s.span.start]);
        out.push_str(&s.replacement);
        pos = s.span.end;
        fixes.push(LocalFix {
            code: d.code.id().to_string(),
            message: d.message.clone(),
            replaced: source[s.span.start..s.span.end].to_string(),
            replacement: s.replacement.clone(),
        });
    }
    out.push_str(&source[pos..]);
    Some((out, fixes))
}

/// Most local fix passes per round (each pass re-checks the program).
const MAX_LOCAL_PASSES: usize = 4;

/// Verifies `program`, applying local fixes while they help. Returns the verdict, the fixes, and
/// the program the verdict is about. The repair loop and `m2rc check --fix` share it, so a fix the
/// command applies is exactly one the loop would have applied before asking the model.
pub fn verify_with_fixes<V: Verifier>(
    verifier: &mut V,
    program: &str,
    local: bool,
) -> (Verdict<V::Output>, Vec<LocalFix>, String) {
    let mut src = program.to_string();
    let mut fixes = Vec::new();
    let mut seen = vec![src.clone()];
    let mut verdict = verifier.verify(&src);
    for _ in 0..MAX_LOCAL_PASSES {
        let Verdict::Rejected { diagnostics, .. } = &verdict else {
            break;
        };
        if !local {
            break;
        }
        let Some((next, more)) = unambiguous_fixes(&src, diagnostics) else {
            break;
        };
        if seen.contains(&next) {
            break;
        }
        seen.push(next.clone());
        src = next;
        fixes.extend(more);
        verdict = verifier.verify(&src);
    }
    (verdict, fixes, src)
}

/// What the previous round left for the repair prompt: the program as checked with its
/// diagnostics, or the reason no program could be taken from the reply.
type PreviousOutcome = Result<(String, Vec<Diagnostic>), Extracted>;

/// Runs one episode: the first prompt, then up to `opts.rounds` repairs.
///
/// `episode` prefixes every request's `custom_id` (`<episode>/round<k>`). Deterministic for a
/// deterministic model and verifier, so a run resumed from a cache replays the same attempts.
pub fn run_episode<M: ChatModel + ?Sized, V: Verifier>(
    model: &M,
    verifier: &mut V,
    first: &Prompt,
    episode: &str,
    opts: &RepairOptions,
) -> Trace<V::Output> {
    let mut attempts: Vec<Attempt> = Vec::new();
    let mut previous: Option<(String, PreviousOutcome)> = None;
    let mut last_program: Option<String> = None;
    let mut last_outcome = EpisodeOutcome::NoProgram {
        reply: "none".into(),
    };
    for round in 0..=opts.rounds {
        let custom_id = format!("{episode}/round{round}");
        let messages = match &previous {
            None => first.messages.clone(),
            Some((reply, Ok((program, diagnostics)))) => repair_messages(
                first,
                reply,
                &Feedback::Diagnostics {
                    program,
                    diagnostics,
                },
            ),
            Some((reply, Err(outcome))) => repair_messages(
                first,
                reply,
                &Feedback::NoProgram {
                    outcome,
                    last_program: last_program.as_deref(),
                },
            ),
        };
        let request = ChatRequest {
            custom_id: custom_id.clone(),
            messages,
        };
        let (reply, mut attempt) =
            match call_model(model, &request, round, &mut attempts, &last_program) {
                Ok(answered) => answered,
                Err(ended) => return ended,
            };
        let extracted = extract(&reply);
        attempt.reply = extracted.kind().to_string();
        let reply_text = reply.content.clone().unwrap_or_default();
        let Extracted::Code { program } = extracted else {
            attempt.outcome = attempt.reply.clone();
            if let Extracted::CutOff { partial: Some(p) } = &extracted {
                attempt.program = Some(p.clone());
            }
            last_outcome = EpisodeOutcome::NoProgram {
                reply: attempt.reply.clone(),
            };
            attempts.push(attempt);
            previous = Some((reply_text, Err(extracted)));
            continue;
        };
        attempt.program = Some(program.clone());
        let (verdict, fixes, checked) = verify_with_fixes(verifier, &program, opts.local_fixes);
        if !fixes.is_empty() {
            attempt.fixed_program = Some(checked.clone());
        }
        attempt.local_fixes = fixes;
        last_program = Some(checked.clone());
        match verdict {
            Verdict::Accepted(output) => {
                attempt.outcome = "accepted".into();
                attempts.push(attempt);
                return Trace {
                    attempts,
                    outcome: EpisodeOutcome::Success { round },
                    output: Some(output),
                    final_program: Some(checked),
                };
            }
            Verdict::Rejected { phase, diagnostics } => {
                attempt.diagnostics = diagnostics.iter().map(DiagRecord::of).collect();
                attempt.outcome = match phase {
                    Phase::Check => "rejected_check",
                    Phase::Ground => "rejected_ground",
                    Phase::Verify => "rejected_verify",
                    Phase::Plan => "plan_failed",
                }
                .into();
                attempts.push(attempt);
                if phase == Phase::Plan {
                    last_outcome = EpisodeOutcome::PlanFailed;
                    if !opts.repair_on_plan_failure {
                        break;
                    }
                } else {
                    last_outcome = EpisodeOutcome::Rejected { phase };
                }
                previous = Some((reply_text, Ok((checked, diagnostics))));
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

#[cfg(test)]
mod tests;
