//! Name resolution: lexical scopes and the shadowing rules.
//!
//! Scopes nest as program > route > stage body / `for` body > lambda. A binding is visible from
//! the statement after its `let` to the end of its scope. A name may shadow one from an enclosing
//! scope (a stage-local `let near_bed` hides a top-level one) but not one in the same scope
//! (E0106), and never the built-in constants `start` / `here` or the enumeration words
//! (`clockwise`, `travel`, ...) (E0112). A binding may share its name with a category: in a slot
//! typed `Category` the word means the category (`objects(bed)`), elsewhere the binding
//! (`go bed`), unless the binding itself has type `Category`.

use crate::check::{Checker, Resolution};
use crate::diagnostic::{Code, Diagnostic};
use m2rc_grammar::ast::{Ident, Span};
use m2rc_stdlib::builtins::{self, Type};
use std::collections::HashMap;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum BindingKind {
    Let,
    LambdaParam,
    ForVar,
}

#[derive(Clone, Debug)]
pub(crate) struct BindingInfo {
    pub name: String,
    pub span: Span,
    /// The whole `let` statement, for the "remove it" suggestion of an unused binding.
    pub stmt: Span,
    pub ty: Type,
    pub kind: BindingKind,
    pub used: bool,
}

/// What kind of region of the program a scope is, for out-of-scope explanations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FrameKind {
    Program,
    Route,
    Stage,
    For,
    Lambda,
}

#[derive(Clone, Debug)]
pub(crate) struct Frame {
    pub kind: FrameKind,
    pub bindings: Vec<BindingInfo>,
    /// Position in `bindings` by name (a frame holds one binding per name), so that a use is
    /// resolved in O(depth) hash look-ups rather than by scanning every earlier `let`.
    pub index: HashMap<String, usize>,
}

impl Checker<'_> {
    pub(crate) fn push_frame(&mut self, kind: FrameKind) {
        self.scopes.push(Frame {
            kind,
            bindings: Vec::new(),
            index: HashMap::new(),
        });
    }

    /// Leaves a scope: reports its unused bindings and remembers them for E0108.
    pub(crate) fn pop_frame(&mut self) {
        let Some(frame) = self.scopes.pop() else {
            return;
        };
        for b in frame.bindings {
            if !b.used
                && !b.name.starts_with('_')
                && b.kind != BindingKind::LambdaParam
                && b.ty != Type::Error
            {
                let what = match b.kind {
                    BindingKind::ForVar => "loop variable",
                    _ => "binding",
                };
                let mut d = Diagnostic::new(
                    Code::UnusedBinding,
                    b.span,
                    format!("unused {what} `{}`", b.name),
                )
                .help(format!(
                    "remove it, or rename it to `_{}` if it is there on purpose",
                    b.name
                ));
                if b.kind == BindingKind::Let {
                    d = d.suggest(b.stmt, "");
                } else {
                    d = d.suggest(b.span, format!("_{}", b.name));
                }
                self.diags.push(d);
            }
            if frame.kind != FrameKind::Lambda {
                self.retired.push((b, frame.kind));
            }
        }
    }

    /// Declares a name in the innermost scope, applying the shadowing rules.
    pub(crate) fn bind(&mut self, ident: &Ident, stmt: Span, ty: Type, kind: BindingKind) {
        if builtins::constant(&ident.name).is_some() || builtins::enum_word(&ident.name).is_some() {
            let what = if builtins::constant(&ident.name).is_some() {
                "constant"
            } else {
                "word"
            };
            self.diags.push(
                Diagnostic::new(
                    Code::RebindBuiltin,
                    ident.span,
                    format!(
                        "`{}` is a built-in {what} and cannot be rebound",
                        ident.name
                    ),
                )
                .help("choose another name")
                .suggest(ident.span, format!("{}_", ident.name)),
            );
            return;
        }
        let Some(frame) = self.scopes.last_mut() else {
            return;
        };
        if let Some(prev) = frame
            .index
            .get(&ident.name)
            .and_then(|&i| frame.bindings.get_mut(i))
        {
            let prev_span = prev.span;
            // The first binding counts as used: the duplicate is the mistake, not the original.
            prev.used = true;
            self.diags.push(
                Diagnostic::new(
                    Code::DuplicateBinding,
                    ident.span,
                    format!("`{}` is already bound in this scope", ident.name),
                )
                .label(prev_span, "first bound here")
                .note(
                    "a name may shadow one from an enclosing scope, but not one in the same scope",
                )
                .help("rename one of them")
                .suggest(ident.span, format!("{}_2", ident.name)),
            );
            return;
        }
        frame.index.insert(ident.name.clone(), frame.bindings.len());
        frame.bindings.push(BindingInfo {
            name: ident.name.clone(),
            span: ident.span,
            stmt,
            ty,
            kind,
            used: false,
        });
    }

    /// The innermost visible binding with this name, marked used.
    pub(crate) fn lookup_binding(&mut self, name: &str) -> Option<(Span, Type, BindingKind)> {
        for frame in self.scopes.iter_mut().rev() {
            if let Some(b) = frame
                .index
                .get(name)
                .and_then(|&i| frame.bindings.get_mut(i))
            {
                b.used = true;
                return Some((b.span, b.ty, b.kind));
            }
        }
        None
    }

    /// Like [`Checker::lookup_binding`] without marking, for deciding how to read a word.
    pub(crate) fn peek_binding(&self, name: &str) -> Option<Type> {
        self.scopes
            .iter()
            .rev()
            .find_map(|f| f.index.get(name).and_then(|&i| f.bindings.get(i)))
            .map(|b| b.ty)
    }

    /// Every visible binding name, innermost first, for did-you-mean.
    pub(crate) fn visible_names(&self) -> Vec<String> {
        let mut v: Vec<String> = Vec::new();
        for f in self.scopes.iter().rev() {
            for b in f.bindings.iter().rev() {
                if !v.contains(&b.name) {
                    v.push(b.name.clone());
                }
            }
        }
        v
    }

    /// Records that `ident` refers to the binding declared at `def`.
    pub(crate) fn resolve_binding(&mut self, ident: &Ident, def: Span, kind: BindingKind) {
        self.resolutions
            .insert(ident.span, Resolution::Binding { def, kind });
    }

    /// A binding that existed but whose scope has ended, for E0108.
    pub(crate) fn retired_binding(&self, name: &str) -> Option<(Span, FrameKind)> {
        self.retired
            .iter()
            .rev()
            .find(|(b, _)| b.name == name)
            .map(|(b, k)| (b.span, *k))
    }
}
