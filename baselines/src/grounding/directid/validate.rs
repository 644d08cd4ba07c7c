//! Reads a Direct ID reply into a [`Grounding`]: every id must be in the catalog, of the kind
//! its place takes, and every constraint must have its arity. All errors are reported at once,
//! each a diagnostic with the JSON pointer of the value at fault, so a repair round (or the
//! simulated model) can fix them where they are.

use super::places::Ref;
use m2rc_compiler::diagnostic::Code;
use m2rc_compiler::intent::GraphDiagnostic;
use m2rc_compiler::ir::Direction;
use m2rc_stdlib::query::MapQuery;
use serde_json::Value;

/// The constraint kinds, as the reply names them.
pub const KINDS: &[&str] = &[
    "require_visit",
    "forbid",
    "prefer_near",
    "prefer_far",
    "prefer_relative",
    "prefer_path_shape",
];

/// Path shapes the catalog can name (a patrol's exit doorway depends on the route: not an id).
pub const SHAPES: &[&str] = &["circle", "follow_wall", "through"];

/// Largest `within_m` accepted (metres): a room-sized halo is a mistake, not a margin.
pub const MAX_WITHIN_M: f64 = 10.0;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    RequireVisit,
    Forbid,
    PreferNear,
    PreferFar,
    PreferRelative,
    PreferPathShape,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeType {
    Circle,
    FollowWall,
    Through,
}

/// One validated constraint; `pointer` is where it is in the reply.
#[derive(Clone, Debug, PartialEq)]
pub struct IdConstraint {
    pub kind: Kind,
    pub refs: Vec<Ref>,
    /// Indices into the segments; `None`: every segment.
    pub segments: Option<Vec<usize>>,
    pub scope: Vec<Ref>,
    pub within_m: Option<f64>,
    /// `prefer_relative`: whether the route keeps closer to the first id (`closer_to`).
    pub closer_to_first: bool,
    pub shape: Option<(ShapeType, Option<Direction>)>,
    pub pointer: String,
}

/// A validated reply: destinations in order, then the constraints.
#[derive(Clone, Debug, PartialEq)]
pub struct Grounding {
    pub segments: Vec<(String, Ref)>,
    pub constraints: Vec<IdConstraint>,
}

struct Check<'a> {
    q: &'a MapQuery<'a>,
    errors: Vec<GraphDiagnostic>,
}

fn shape(pointer: &str, message: impl Into<String>, help: Option<String>) -> GraphDiagnostic {
    GraphDiagnostic::new(Code::GraphShape, pointer, message, help)
}

/// Edit distance, for telling a misspelled `object`/`room` prefix.
fn edits(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// The one existing id a misspelling stands for: same number, the kind word misspelled. A
/// neighbouring number is another object, so it is never suggested.
fn respelled(q: &MapQuery, id: &str) -> Option<String> {
    let cut = id.rfind(|c: char| !c.is_ascii_digit())? + 1;
    let (head, digits) = id.split_at(cut);
    let head = head
        .trim_end_matches(['_', '-', ' ', '#'])
        .to_ascii_lowercase();
    if digits.is_empty() || head.is_empty() {
        return None;
    }
    let found: Vec<String> = [("object", "object_"), ("room", "room_")]
        .into_iter()
        .filter(|(w, _)| edits(&head, w) <= 2)
        .map(|(_, p)| format!("{p}{digits}"))
        .filter(|c| Ref::parse(c).is_some_and(|r| r.exists(q)))
        .collect();
    (found.len() == 1).then(|| found[0].clone())
}

impl Check<'_> {
    fn err(&mut self, d: GraphDiagnostic) {
        self.errors.push(d);
    }

    /// One id; `allowed` says which kinds the place takes (`what` names it for the message).
    fn id(
        &mut self,
        v: &Value,
        pointer: &str,
        allowed: &[fn(Ref) -> bool],
        what: &str,
    ) -> Option<Ref> {
        let Some(s) = v.as_str() else {
            self.err(shape(
                pointer,
                format!("{what} must be a catalog id (a string), not {v}"),
                None,
            ));
            return None;
        };
        let found = Ref::parse(s).filter(|r| r.exists(self.q));
        let Some(r) = found else {
            let help = respelled(self.q, s).map(|c| format!("write `{c}`"));
            self.err(GraphDiagnostic::new(
                Code::CatalogUnknownId,
                pointer,
                format!("`{s}` is not an id of the scene catalog"),
                help.or_else(|| Some("use an id exactly as the catalog lists it".into())),
            ));
            return None;
        };
        if !allowed.iter().any(|ok| ok(r)) {
            self.err(shape(
                pointer,
                format!(
                    "`{s}` is {} and {what} cannot be {}",
                    r.kind_word(),
                    r.kind_word()
                ),
                None,
            ));
            return None;
        }
        Some(r)
    }

    fn ids(
        &mut self,
        v: &Value,
        pointer: &str,
        allowed: &[fn(Ref) -> bool],
        what: &str,
    ) -> Option<Vec<Ref>> {
        let Some(items) = v.as_array() else {
            self.err(shape(
                pointer,
                format!("{what} must be an array of catalog ids"),
                None,
            ));
            return None;
        };
        let mut out = Vec::new();
        let mut ok = true;
        for (i, item) in items.iter().enumerate() {
            match self.id(item, &format!("{pointer}/{i}"), allowed, what) {
                Some(r) => out.push(r),
                None => ok = false,
            }
        }
        ok.then_some(out)
    }
}

fn is_place(r: Ref) -> bool {
    !matches!(r, Ref::Start)
}
fn is_any(_: Ref) -> bool {
    true
}
fn is_room(r: Ref) -> bool {
    matches!(r, Ref::Room(_))
}

fn keys_known(c: &mut Check, v: &Value, pointer: &str, known: &[&str]) {
    if let Some(o) = v.as_object() {
        for k in o.keys().filter(|k| !known.contains(&k.as_str())) {
            c.err(shape(
                &format!("{pointer}/{}", escape(k)),
                format!("unknown key `{k}`"),
                Some(format!("the keys here are: {}", known.join(", "))),
            ));
        }
    }
}

/// A JSON-pointer token (RFC 6901).
pub fn escape(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

/// Validates a reply against the catalog of `q`'s map.
pub fn validate(reply: &Value, q: &MapQuery) -> Result<Grounding, Vec<GraphDiagnostic>> {
    let mut c = Check {
        q,
        errors: Vec::new(),
    };
    keys_known(&mut c, reply, "", &["segments", "constraints"]);
    let mut segments: Vec<(String, Ref)> = Vec::new();
    // Every well-named segment, also those whose target is wrong: a constraint naming one is
    // not a second error.
    let mut names: Vec<String> = Vec::new();
    match reply.get("segments").and_then(Value::as_array) {
        Some(items) if !items.is_empty() => {
            for (i, s) in items.iter().enumerate() {
                let p = format!("/segments/{i}");
                keys_known(&mut c, s, &p, &["id", "target_id"]);
                let id = match s.get("id").and_then(Value::as_str) {
                    Some(id) if !id.trim().is_empty() => id.to_string(),
                    _ => {
                        c.err(shape(
                            &format!("{p}/id"),
                            "a segment needs an `id` (a non-empty string)",
                            None,
                        ));
                        continue;
                    }
                };
                if names.contains(&id) {
                    c.err(shape(
                        &format!("{p}/id"),
                        format!("segment id `{id}` is used twice"),
                        None,
                    ));
                }
                names.push(id.clone());
                let target = s.get("target_id").unwrap_or(&Value::Null);
                if let Some(r) = c.id(
                    target,
                    &format!("{p}/target_id"),
                    &[is_any],
                    "a segment's target",
                ) {
                    segments.push((id, r));
                }
            }
        }
        _ => c.err(shape(
            "/segments",
            "the reply needs `segments`: a non-empty array of {id, target_id}",
            None,
        )),
    }
    let mut constraints = Vec::new();
    match reply.get("constraints") {
        None | Some(Value::Null) => {}
        Some(Value::Array(items)) => {
            for (i, v) in items.iter().enumerate() {
                if let Some(k) = constraint(&mut c, v, &format!("/constraints/{i}"), &names) {
                    constraints.push(k);
                }
            }
        }
        Some(_) => c.err(shape(
            "/constraints",
            "`constraints` must be an array",
            None,
        )),
    }
    if c.errors.is_empty() {
        Ok(Grounding {
            segments,
            constraints,
        })
    } else {
        Err(c.errors)
    }
}

fn arity(c: &mut Check, p: &str, kind: &str, n: usize, lo: usize, hi: usize) -> bool {
    if (lo..=hi).contains(&n) {
        return true;
    }
    let want = match (lo, hi) {
        (a, b) if a == b => format!("exactly {a}"),
        (a, usize::MAX) => format!("at least {a}"),
        (a, b) => format!("{a} to {b}"),
    };
    c.err(GraphDiagnostic::new(
        Code::CatalogArity,
        &format!("{p}/ref_ids"),
        format!("`{kind}` takes {want} id(s) in `ref_ids`, and {n} were given"),
        None,
    ));
    false
}

fn constraint(c: &mut Check, v: &Value, p: &str, segments: &[String]) -> Option<IdConstraint> {
    keys_known(
        c,
        v,
        p,
        &[
            "kind",
            "ref_ids",
            "segment_ids",
            "spatial_scope_ids",
            "within_m",
            "relation",
            "path_shape",
            "source_text",
        ],
    );
    let kind_text = v.get("kind").and_then(Value::as_str).unwrap_or("");
    let kind = match kind_text {
        "require_visit" => Kind::RequireVisit,
        "forbid" => Kind::Forbid,
        "prefer_near" => Kind::PreferNear,
        "prefer_far" => Kind::PreferFar,
        "prefer_relative" => Kind::PreferRelative,
        "prefer_path_shape" => Kind::PreferPathShape,
        _ => {
            c.err(shape(
                &format!("{p}/kind"),
                format!("`{kind_text}` is not a constraint kind"),
                Some(format!("the kinds are: {}", KINDS.join(", "))),
            ));
            return None;
        }
    };
    let mut ok = true;
    let mut shape_spec = None;
    if kind == Kind::PreferPathShape {
        shape_spec = path_shape(c, v.get("path_shape"), &format!("{p}/path_shape"));
        ok &= shape_spec.is_some();
    }
    let allowed: &[fn(Ref) -> bool] = match (kind, shape_spec) {
        (Kind::PreferPathShape, Some((ShapeType::FollowWall, _))) => &[is_room],
        (Kind::PreferNear | Kind::PreferFar, _) => &[is_any],
        _ => &[is_place],
    };
    let refs = match v.get("ref_ids") {
        Some(ids) => c.ids(
            ids,
            &format!("{p}/ref_ids"),
            allowed,
            &format!("a `{kind_text}` id"),
        ),
        None => {
            c.err(shape(
                &format!("{p}/ref_ids"),
                format!("`{kind_text}` needs `ref_ids`"),
                None,
            ));
            None
        }
    };
    let n = v
        .get("ref_ids")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    let (lo, hi) = match (kind, shape_spec) {
        (Kind::Forbid, _) => (1, usize::MAX),
        (Kind::PreferRelative, _) => (2, 2),
        (Kind::PreferPathShape, Some((ShapeType::Through, _))) => (2, 4),
        _ => (1, 1),
    };
    ok &= v.get("ref_ids").is_none() || arity(c, p, kind_text, n, lo, hi);
    let mut closer_to_first = true;
    if kind == Kind::PreferRelative {
        match v.get("relation").and_then(Value::as_str) {
            Some("closer_to") => {}
            Some("farther_from") => closer_to_first = false,
            _ => {
                c.err(shape(
                    &format!("{p}/relation"),
                    "`prefer_relative` needs `relation`: `closer_to` or `farther_from` (the first id)",
                    None,
                ));
                ok = false;
            }
        }
    }
    let within_m = match v.get("within_m") {
        None | Some(Value::Null) => None,
        Some(w) => match w.as_f64() {
            Some(x)
                if matches!(kind, Kind::Forbid | Kind::PreferNear | Kind::PreferFar)
                    && x > 0.0
                    && x <= MAX_WITHIN_M =>
            {
                Some(x)
            }
            _ => {
                c.err(shape(
                    &format!("{p}/within_m"),
                    format!("`within_m` is a distance in metres above 0 and at most {MAX_WITHIN_M}, for forbid, prefer_near and prefer_far only"),
                    None,
                ));
                ok = false;
                None
            }
        },
    };
    let segs = match v.get("segment_ids") {
        None | Some(Value::Null) => None,
        Some(Value::Array(items)) => {
            let mut idx = Vec::new();
            for (i, s) in items.iter().enumerate() {
                match s
                    .as_str()
                    .and_then(|s| segments.iter().position(|n| n == s))
                {
                    Some(k) => idx.push(k),
                    None => {
                        let names: Vec<&str> = segments.iter().map(String::as_str).collect();
                        c.err(shape(
                            &format!("{p}/segment_ids/{i}"),
                            format!("{s} is not the id of a segment"),
                            Some(format!("the segments are: {}", names.join(", "))),
                        ));
                        ok = false;
                    }
                }
            }
            idx.sort_unstable();
            idx.dedup();
            Some(idx)
        }
        Some(_) => {
            c.err(shape(
                &format!("{p}/segment_ids"),
                "`segment_ids` must be an array of segment ids",
                None,
            ));
            ok = false;
            None
        }
    };
    if kind == Kind::RequireVisit && segs.as_ref().is_none_or(|s| s.len() != 1) {
        c.err(shape(
            &format!("{p}/segment_ids"),
            "`require_visit` is passed on the way to one destination: give exactly one segment id",
            None,
        ));
        ok = false;
    }
    let scope = match v.get("spatial_scope_ids") {
        None | Some(Value::Null) => Vec::new(),
        Some(ids) => match c.ids(
            ids,
            &format!("{p}/spatial_scope_ids"),
            &[is_place],
            "a spatial scope",
        ) {
            Some(s) => s,
            None => {
                ok = false;
                Vec::new()
            }
        },
    };
    let refs = refs?;
    ok.then_some(IdConstraint {
        kind,
        refs,
        segments: segs,
        scope,
        within_m,
        closer_to_first,
        shape: shape_spec,
        pointer: p.to_string(),
    })
}

fn path_shape(c: &mut Check, v: Option<&Value>, p: &str) -> Option<(ShapeType, Option<Direction>)> {
    let Some(v) = v.filter(|v| v.is_object()) else {
        c.err(shape(
            p,
            "`prefer_path_shape` needs `path_shape`: {type, direction?}",
            None,
        ));
        return None;
    };
    keys_known(c, v, p, &["type", "direction"]);
    let t = match v.get("type").and_then(Value::as_str) {
        Some("circle") => ShapeType::Circle,
        Some("follow_wall") => ShapeType::FollowWall,
        Some("through") => ShapeType::Through,
        other => {
            c.err(shape(
                &format!("{p}/type"),
                format!("`{}` is not a path shape", other.unwrap_or("")),
                Some(format!("the shapes are: {}", SHAPES.join(", "))),
            ));
            return None;
        }
    };
    let d = match (t, v.get("direction")) {
        (_, None | Some(Value::Null)) => None,
        (ShapeType::Circle | ShapeType::FollowWall, Some(d)) if d == "clockwise" => {
            Some(Direction::Clockwise)
        }
        (ShapeType::Circle | ShapeType::FollowWall, Some(d)) if d == "counterclockwise" => {
            Some(Direction::Counterclockwise)
        }
        _ => {
            c.err(shape(
                &format!("{p}/direction"),
                "`direction` is `clockwise` or `counterclockwise`, for circle and follow_wall only",
                None,
            ));
            return None;
        }
    };
    Some((t, d))
}
