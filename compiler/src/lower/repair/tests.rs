use super::*;
use crate::lower::catalog::{CatalogMode, SceneCatalog};
use crate::lower::prompt::{Prompt, PromptOptions};
use crate::lower::{ChatReply, Usage};
use m2rc_stdlib::vocab::Vocabulary;
use std::cell::RefCell;

/// Replies in order and remembers every request.
struct Scripted {
    replies: RefCell<Vec<Result<ChatReply, ChatError>>>,
    seen: RefCell<Vec<ChatRequest>>,
}

impl Scripted {
    fn new(replies: Vec<Result<ChatReply, ChatError>>) -> Self {
        Scripted {
            replies: RefCell::new(replies.into_iter().rev().collect()),
            seen: RefCell::new(Vec::new()),
        }
    }
}

impl ChatModel for Scripted {
    fn complete(&self, request: &ChatRequest) -> Result<ChatReply, ChatError> {
        self.seen.borrow_mut().push(request.clone());
        self.replies
            .borrow_mut()
            .pop()
            .unwrap_or_else(|| Err(ChatError::Failed("script exhausted".into())))
    }
}

fn code(program: &str) -> Result<ChatReply, ChatError> {
    Ok(ChatReply {
        choices: 1,
        content: Some(format!("```m2r\n{program}```")),
        finish_reason: Some("stop".into()),
        usage: Usage {
            prompt_tokens: Some(100),
            completion_tokens: Some(20),
        },
        latency_ms: 5.0,
        refusal: None,
    })
}

fn check_only(source: &str) -> Verdict<()> {
    let r = crate::check(source, &Vocabulary::benchmark());
    if r.has_errors() {
        Verdict::Rejected {
            phase: Phase::of_errors(&r.diagnostics),
            diagnostics: r.diagnostics,
        }
    } else {
        Verdict::Accepted(())
    }
}

fn prompt() -> Prompt {
    let map = m2rc_stdlib::demo::demo_map().expect("demo");
    Prompt::new(
        &map.map_id,
        &SceneCatalog::from_map(&map, CatalogMode::Counts),
        "Go to the bed, keep away from the sofa.",
        &PromptOptions::default(),
    )
}

#[test]
fn local_fixes_are_applied_and_only_the_rest_reaches_the_model() {
    // `chiar` has one suggestion (local); `area_near(objects(bed))` has two (`.only()`,
    // `.nearest()`).
    let bad = "let c = objects(chiar).nearest(start)\nroute {\n  go area_near(objects(bed))\n  avoid c\n}\n";
    let good = "let c = objects(chair).nearest(start)\nroute {\n  go area_near(objects(bed).nearest(start))\n  avoid c\n}\n";
    let model = Scripted::new(vec![code(bad), code(good)]);
    let mut v = check_only;
    let t = run_episode(
        &model,
        &mut v,
        &prompt(),
        "demo/e1",
        &RepairOptions::default(),
    );
    assert_eq!(t.outcome, EpisodeOutcome::Success { round: 1 });
    assert_eq!(t.attempts.len(), 2);
    let a0 = &t.attempts[0];
    assert_eq!(a0.local_fixes.len(), 1, "{a0:?}");
    assert_eq!(a0.local_fixes[0].replacement, "chair");
    assert_eq!(a0.outcome, "rejected_check");
    let seen = model.seen.borrow();
    assert_eq!(seen[1].custom_id, "demo/e1/round1");
    let repair = &seen[1].messages.last().unwrap().content;
    let remaining = &a0.diagnostics[0].code;
    assert!(repair.contains(&format!("error[{remaining}]")), "{repair}");
    assert!(repair.contains(&format!("\"code\": \"{remaining}\"")));
    // The locally fixed error never reaches the model: the program it sees says `chair`.
    assert!(!repair.contains("chiar"), "{repair}");
    assert!(!repair.contains("E0401"));
    assert_eq!(t.tokens(), (200, 40));
}

#[test]
fn a_program_fixed_locally_needs_no_second_request() {
    let bad = "route {\n  go objects(chiar).nearest(start)\n}\n";
    let model = Scripted::new(vec![code(bad)]);
    let mut v = check_only;
    let t = run_episode(&model, &mut v, &prompt(), "e", &RepairOptions::default());
    assert_eq!(t.outcome, EpisodeOutcome::Success { round: 0 });
    assert_eq!(model.seen.borrow().len(), 1);
    assert_eq!(t.local_fix_count(), 1);
    assert!(t.final_program.unwrap().contains("objects(chair)"));
}

#[test]
fn rounds_are_bounded_and_non_code_replies_are_answered() {
    let no_code = Ok(ChatReply {
        choices: 1,
        content: Some("The bed is upstairs.".into()),
        finish_reason: Some("stop".into()),
        ..ChatReply::default()
    });
    let bad = "route {\n  go area_near(objects(bed))\n}\n";
    let model = Scripted::new(vec![no_code, code(bad), code(bad), code(bad), code(bad)]);
    let mut v = check_only;
    let opts = RepairOptions {
        rounds: 2,
        ..RepairOptions::default()
    };
    let t = run_episode(&model, &mut v, &prompt(), "e", &opts);
    assert_eq!(t.attempts.len(), 3);
    assert_eq!(t.attempts[0].outcome, "no_code");
    assert_eq!(
        t.outcome,
        EpisodeOutcome::Rejected {
            phase: Phase::Check
        }
    );
    let seen = model.seen.borrow();
    assert!(seen[1].messages[3].content.contains("no ```m2r block"));
    assert_eq!(seen.len(), 3);
}

#[test]
fn plan_failures_end_the_episode_unless_asked() {
    let prog = "route {\n  go objects(bed).nearest(start)\n}\n";
    let plan_fail = |_: &str| -> Verdict<()> {
        Verdict::Rejected {
            phase: Phase::Plan,
            diagnostics: vec![],
        }
    };
    let model = Scripted::new(vec![code(prog), code(prog)]);
    let mut v = plan_fail;
    let t = run_episode(&model, &mut v, &prompt(), "e", &RepairOptions::default());
    assert_eq!(t.outcome, EpisodeOutcome::PlanFailed);
    assert_eq!(model.seen.borrow().len(), 1);
    let model = Scripted::new(vec![code(prog), code(prog)]);
    let opts = RepairOptions {
        rounds: 1,
        repair_on_plan_failure: true,
        ..RepairOptions::default()
    };
    let t = run_episode(&model, &mut v, &prompt(), "e", &opts);
    assert_eq!(model.seen.borrow().len(), 2);
    assert_eq!(t.outcome, EpisodeOutcome::PlanFailed);
}

#[test]
fn pending_and_failed_requests_end_with_their_own_outcome() {
    let model = Scripted::new(vec![Err(ChatError::Pending("e/round0".into()))]);
    let mut v = check_only;
    let t = run_episode(&model, &mut v, &prompt(), "e", &RepairOptions::default());
    assert_eq!(t.outcome.status(), "pending");
    let model = Scripted::new(vec![Err(ChatError::Failed("HTTP 500".into()))]);
    let t = run_episode(&model, &mut v, &prompt(), "e", &RepairOptions::default());
    assert_eq!(t.outcome.status(), "model_failed");
    assert_eq!(t.attempts[0].error.as_deref(), Some("HTTP 500"));
}

#[test]
fn overlapping_or_ambiguous_suggestions_are_not_applied() {
    let src = "route {\n  go area_near(objects(bed))\n}\n";
    let r = crate::check(src, &Vocabulary::benchmark());
    assert!(unambiguous_fixes(src, &r.diagnostics).is_none());
}
