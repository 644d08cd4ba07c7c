//! The `.m2r` route language front end: tokens (logos), grammar (LALRPOP), the AST with byte spans,
//! and a pretty-printer.
//!
//! Entry points: [`parse()`] (never fails: a program with `Error` nodes plus every error),
//! [`print()`] / [`print_with_comments`] (canonical formatting), and [`ParseError`] with its stable
//! `E00xx` codes.

pub mod ast;
mod conditional;
pub mod erase;
pub mod error;
pub mod lexer;
pub mod parse;
pub mod print;

pub use erase::{erase_expr_spans, erase_spans, same_modulo_spans};
pub use error::{Fix, ParseError, ParseErrorKind};
pub use parse::{
    MAX_STATEMENT_TOKENS, MAX_SYNTAX_ERRORS, Parsed, expected_words, parse, parse_expr,
};
pub use print::{format_f64, print, print_expr, print_with_comments};
