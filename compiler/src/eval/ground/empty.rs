//! What an empty selection's diagnostic (E0501, E0503) says about the map: a category the map
//! lacks entirely, or where the map does have it. The writer then sees at once whether the
//! category or the filter is wrong, and a program written for another scene reads as such ("the
//! map `demo` has 2 `garbage_can`, in kitchen_1 and bathroom_1").

use crate::eval::Grounder;
use crate::eval::value::room_name;
use m2rc_grammar::ast::Span;
use m2rc_stdlib::map::SemanticMap;

/// Rooms named in one note before the rest are counted ("and 4 more rooms").
const MAX_ROOMS_NAMED: usize = 6;

impl Grounder<'_, '_> {
    /// Notes on the categories the selection at `span` starts from (`objects(a | b)` or
    /// `rooms(c)`): those the map lacks, then where the others are.
    pub(super) fn category_notes(&self, span: Span) -> Vec<String> {
        let Some(text) = self.source.get(span.start..span.end) else {
            return Vec::new();
        };
        let cats = categories_in(text);
        let map = self.q.map();
        let (present, missing): (Vec<&str>, Vec<&str>) = cats.into_iter().partition(|c| {
            map.objects.iter().any(|o| o.category == *c)
                || map.rooms.iter().any(|r| r.category == *c)
        });
        let mut notes = Vec::new();
        if !missing.is_empty() {
            notes.push(format!("this map has no `{}` at all", missing.join("`, `")));
        }
        notes.extend(present.into_iter().filter_map(|c| where_is(map, c)));
        notes
    }
}

/// The categories of the first `objects(...)` or `rooms(...)` in a selection's source text.
fn categories_in(text: &str) -> Vec<&str> {
    let inner = text
        .split("objects(")
        .nth(1)
        .or_else(|| text.split("rooms(").nth(1));
    let Some(inner) = inner.and_then(|i| i.split(')').next()) else {
        return Vec::new();
    };
    inner
        .split('|')
        .map(str::trim)
        .filter(|c| !c.is_empty() && c.chars().all(|ch| ch.is_ascii_alphanumeric() || ch == '_'))
        .collect()
}

/// "the map `demo` has 2 `garbage_can`, in kitchen_1 and bathroom_1" or "the map `demo` has 3
/// `bedroom` rooms: bedroom_1, bedroom_2 and bedroom_3".
fn where_is(map: &SemanticMap, category: &str) -> Option<String> {
    let rooms: Vec<String> = map
        .rooms
        .iter()
        .filter(|r| r.category == category)
        .map(room_name)
        .collect();
    if !rooms.is_empty() {
        return Some(format!(
            "the map `{}` has {} `{category}` room{}: {}",
            map.map_id,
            rooms.len(),
            if rooms.len() == 1 { "" } else { "s" },
            listing(rooms)
        ));
    }
    // Objects per room, in room order; objects in no room last.
    let mut per_room: Vec<(Option<u32>, usize)> = Vec::new();
    let mut total = 0;
    for o in map.objects.iter().filter(|o| o.category == category) {
        total += 1;
        match per_room.iter_mut().find(|(r, _)| *r == o.room) {
            Some((_, k)) => *k += 1,
            None => per_room.push((o.room, 1)),
        }
    }
    if total == 0 {
        return None;
    }
    per_room.sort_by_key(|(r, _)| r.map_or(u32::MAX, |r| r));
    let places: Vec<String> = per_room
        .into_iter()
        .map(|(r, k)| {
            let name = match r.and_then(|r| map.room(r)) {
                Some(room) => room_name(room),
                None => "no room".to_string(),
            };
            if k > 1 { format!("{name} ({k})") } else { name }
        })
        .collect();
    Some(format!(
        "the map `{}` has {total} `{category}`, in {}",
        map.map_id,
        listing(places)
    ))
}

/// `a`, `a and b`, `a, b and c`; past [`MAX_ROOMS_NAMED`], `a, b, ... and 3 more rooms`.
fn listing(mut names: Vec<String>) -> String {
    if names.len() > MAX_ROOMS_NAMED {
        let rest = names.len() - (MAX_ROOMS_NAMED - 1);
        names.truncate(MAX_ROOMS_NAMED - 1);
        names.push(format!("{rest} more rooms"));
    }
    match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, init)) => format!("{} and {last}", init.join(", ")),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_read_as_prose() {
        assert_eq!(listing(vec!["a".into()]), "a");
        assert_eq!(listing(vec!["a".into(), "b".into()]), "a and b");
        let many: Vec<String> = (1..=9).map(|i| format!("r{i}")).collect();
        assert_eq!(listing(many), "r1, r2, r3, r4, r5 and 4 more rooms");
        assert_eq!(
            categories_in("objects(bed | sofa).in(bedroom)"),
            vec!["bed", "sofa"]
        );
        assert_eq!(categories_in("rooms(kitchen)"), vec!["kitchen"]);
        assert!(categories_in("rooms().where(r => r.x())").is_empty());
    }
}
