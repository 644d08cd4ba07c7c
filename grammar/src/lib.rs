//! The `.m2r` route language front end: tokens (logos), grammar (LALRPOP), the AST with byte spans,
//! and a pretty-printer.

pub mod ast;
