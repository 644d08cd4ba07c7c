//! `m2rc prompt`: prints the exact messages the model would get for an instruction on a map, or,
//! with `--repair-of prog.m2r`, the repair request for that program (after the local fixes the
//! repair loop would apply), so people can see what the model sees.

use crate::io::{read_to_string_capped, unusable};
use anyhow::{Context, Result, anyhow};
use clap::{Args, ValueEnum};
use m2rc_benchmark::limits::{MAX_PROGRAM_BYTES, check_program_size};
use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan};
use m2rc_compiler::lower::prompt::{Feedback, repair_messages};
use m2rc_compiler::lower::repair::unambiguous_fixes;
use m2rc_compiler::lower::{Message, Prompt, SceneCatalog};
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct PromptArgs {
    /// The route instruction, in natural language.
    pub instruction: String,
    /// Map file or `demo`.
    #[arg(long)]
    pub map: String,
    /// Show the repair request for this program instead of the first request.
    #[arg(long)]
    pub repair_of: Option<PathBuf>,
    /// `text` shows the messages for reading; `json` prints them exactly as they are sent.
    #[arg(long, value_enum, default_value_t = PromptFormat::Text)]
    pub format: PromptFormat,
    #[command(flatten)]
    pub lower: m2rc_llm::LowerArgs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PromptFormat {
    Text,
    Json,
}

/// The reference's prompt template alone, in bytes (grounding2route-method.md §6).
pub const REFERENCE_TEMPLATE_BYTES: usize = 10_800;

/// Refuses an instruction with nothing in it: the prompt around it would be sent in full and the
/// model asked to route nothing.
pub fn check_instruction(instruction: &str) -> Result<()> {
    if instruction.trim().is_empty() {
        return Err(unusable(anyhow!(
            "the instruction is empty: give the route in words, e.g. \"Go to the bed in the smallest bedroom\""
        )));
    }
    Ok(())
}

pub fn run(args: PromptArgs) -> Result<ExitCode> {
    check_instruction(&args.instruction)?;
    if let (Some(path), 0) = (&args.repair_of, args.lower.repair_rounds) {
        return Err(unusable(anyhow!(
            "--repair-of {}: with --repair-rounds 0 the repair loop never sends a repair request; \
             drop --repair-rounds 0 to see the one it would send",
            path.display()
        )));
    }
    let map = m2rc_stdlib::load::load_map(&args.map)
        .with_context(|| format!("cannot load map `{}`", args.map))?;
    let opts = args.lower.prompt_options();
    let catalog = SceneCatalog::from_map(&map, opts.catalog);
    let first = Prompt::new(&map.map_id, &catalog, &args.instruction, &opts);
    let messages: Vec<Message> = match &args.repair_of {
        None => first.messages.clone(),
        Some(path) => {
            let source = read_to_string_capped(path, MAX_PROGRAM_BYTES, "a program")?;
            let name = crate::io::display_name(path);
            check_program_size(&source).map_err(|m| anyhow!("{name}: {m}"))?;
            let pipeline = PipelineOptions::default();
            let mut program = source.clone();
            let mut diags = match compile_and_plan(&program, &map, &pipeline) {
                Ok(_) => Vec::new(),
                Err(d) => d,
            };
            if !args.lower.no_local_fixes {
                for _ in 0..4 {
                    let Some((next, _)) = unambiguous_fixes(&program, &diags) else {
                        break;
                    };
                    program = next;
                    diags = match compile_and_plan(&program, &map, &pipeline) {
                        Ok(_) => Vec::new(),
                        Err(d) => d,
                    };
                }
            }
            if !diags.iter().any(|d| d.is_error()) {
                eprintln!(
                    "{} compiles and plans on this map{}: a repair round would not be needed",
                    path.display(),
                    if program != source {
                        " after local fixes"
                    } else {
                        ""
                    }
                );
            }
            repair_messages(
                &first,
                &format!("```m2r\n{source}```"),
                &Feedback::Diagnostics {
                    program: &program,
                    diagnostics: &diags,
                },
            )
        }
    };
    let chars: usize = messages.iter().map(|m| m.content.chars().count()).sum();
    let bytes: usize = messages.iter().map(|m| m.content.len()).sum();
    let tokens: usize = messages
        .iter()
        .map(|m| m2rc_compiler::lower::estimate_tokens(&m.content))
        .sum();
    match args.format {
        PromptFormat::Json => println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "messages": messages,
                "chars": chars,
                "bytes": bytes,
                "estimated_tokens": tokens,
            }))?
        ),
        PromptFormat::Text => {
            for m in &messages {
                let role = serde_json::to_value(m.role)?;
                println!("===== {} =====", role.as_str().unwrap_or("?"));
                println!("{}", m.content.trim_end());
            }
            eprintln!(
                "prompt: {} message(s), {bytes} bytes, about {tokens} tokens (4 characters a token); \
the reference's template alone is about {} bytes, before its instruction and catalog",
                messages.len(),
                REFERENCE_TEMPLATE_BYTES
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
