//! Category words: checked against the map's vocabulary when a map is given, otherwise against
//! the benchmark's 97 object and 4 room categories, with synonyms resolved or suggested.

use crate::check::{Checker, Resolution};
use crate::diagnostic::{Code, Diagnostic};
use crate::slot::CatCtx;
use crate::suggest;
use m2rc_grammar::ast::Ident;
use m2rc_stdlib::builtins::Type;
use m2rc_stdlib::vocab::{CategoryKind, Lookup, VocabSource};

fn kind_word(k: CategoryKind) -> &'static str {
    match k {
        CategoryKind::Object => "object",
        CategoryKind::Room => "room",
    }
}

impl Checker<'_> {
    /// A bare word in a category slot.
    pub(crate) fn category_name(&mut self, id: &Ident, ctx: CatCtx) -> Type {
        let word = id.name.as_str();
        match self.vocab.lookup(word) {
            Lookup::Found(kind) => {
                self.resolve_category(id, word.to_string(), kind);
                self.check_kind(id, word, kind, ctx);
                Type::Category
            }
            Lookup::Synonym(canon, kind) => {
                self.report(
                    Diagnostic::new(
                        Code::SynonymResolved,
                        id.span,
                        format!("`{word}` is read as the category `{canon}`"),
                    )
                    .help(format!("write `{canon}`"))
                    .suggest(id.span, canon.clone()),
                );
                self.resolve_category(id, canon.clone(), kind);
                self.check_kind(id, &canon, kind, ctx);
                Type::Category
            }
            Lookup::Ambiguous(cands) => {
                let union = cands.join(" | ");
                let mut d = Diagnostic::new(
                    Code::AmbiguousCategory,
                    id.span,
                    format!("`{word}` could mean {}", or_list(&cands)),
                )
                .help(format!(
                    "name the category, or write the union `{union}` to accept all of them"
                ));
                for c in &cands {
                    d = d.suggest(id.span, c.clone());
                }
                d = d.suggest(id.span, union);
                self.report(d);
                Type::Error
            }
            Lookup::NotInMap(canon, kind) => {
                let map = match &self.vocab.source {
                    VocabSource::Map(m) => m.clone(),
                    VocabSource::Benchmark => "the vocabulary".to_string(),
                };
                let same_kind: Vec<&str> = self
                    .vocab
                    .all()
                    .filter(|(_, k)| *k == kind)
                    .map(|(c, _)| c)
                    .collect();
                let near = suggest::ranked(&canon, same_kind.iter().copied(), 5);
                let mut d = Diagnostic::new(
                    Code::CategoryNotInMap,
                    id.span,
                    format!(
                        "map `{map}` has no {} of category `{canon}`",
                        kind_word(kind)
                    ),
                );
                if !near.is_empty() {
                    d = d.note(format!(
                        "{} categories in this map include: {}",
                        kind_word(kind),
                        near.join(", ")
                    ));
                }
                if let Some(best) = suggest::best(&canon, same_kind.iter().copied()) {
                    d = d
                        .help(format!("did you mean `{best}`?"))
                        .suggest(id.span, best);
                }
                self.report(d);
                Type::Error
            }
            Lookup::Unknown => {
                self.unknown_category(id, ctx);
                Type::Error
            }
        }
    }

    fn resolve_category(&mut self, id: &Ident, name: String, kind: CategoryKind) {
        self.resolutions
            .insert(id.span, Resolution::Category { name, kind });
    }

    /// `objects(kitchen)` and `rooms(bed)`.
    fn check_kind(&mut self, id: &Ident, canon: &str, kind: CategoryKind, ctx: CatCtx) {
        let Some(want) = ctx.want else { return };
        if want == kind {
            return;
        }
        let (code, right) = match kind {
            CategoryKind::Room => (Code::RoomCategoryForObjects, "rooms"),
            CategoryKind::Object => (Code::ObjectCategoryForRooms, "objects"),
        };
        let mut d = Diagnostic::new(
            code,
            id.span,
            format!(
                "`{canon}` is a {} category, but {} categories are expected here",
                kind_word(kind),
                kind_word(want)
            ),
        );
        if let Some(func) = ctx.func {
            d = d
                .label(
                    func,
                    format!("this query takes {} categories", kind_word(want)),
                )
                .help(format!("write `{right}({canon})`"))
                .suggest(func, right);
        } else {
            d = d.help(format!(
                "query {} separately with `{right}({canon})`",
                kind_word(kind)
            ));
        }
        self.report(d);
    }

    fn unknown_category(&mut self, id: &Ident, ctx: CatCtx) {
        let word = id.name.as_str();
        let preferred: Vec<&str> = self
            .vocab
            .all()
            .filter(|(_, k)| ctx.want.is_none_or(|w| w == *k))
            .map(|(c, _)| c)
            .collect();
        let all: Vec<&str> = self.vocab.all().map(|(c, _)| c).collect();
        let best = suggest::best(word, preferred.iter().copied())
            .or_else(|| suggest::best(word, all.iter().copied()));
        let source = match &self.vocab.source {
            VocabSource::Map(m) => format!("map `{m}`"),
            VocabSource::Benchmark => "the benchmark vocabulary".to_string(),
        };
        let mut d = Diagnostic::new(
            Code::UnknownCategory,
            id.span,
            format!("unknown category `{word}`"),
        )
        .note(format!("categories are checked against {source}"));
        if let Some(best) = best {
            d = d
                .help(format!("did you mean `{best}`?"))
                .suggest(id.span, best);
        } else if let Some(ty) = self.peek_binding(word) {
            d = d.note(format!(
                "`{word}` is a binding of type `{ty}`, not a category"
            ));
        } else {
            let near = suggest::ranked(word, preferred.iter().copied(), 5);
            d = d.note(format!("closest categories: {}", near.join(", ")));
        }
        self.report(d);
    }
}

fn or_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => format!("`{one}`"),
        [init @ .., last] => {
            let head: Vec<String> = init.iter().map(|s| format!("`{s}`")).collect();
            format!("{} or `{last}`", head.join(", "))
        }
    }
}
