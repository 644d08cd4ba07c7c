//! The registry of diagnostic codes: every code m2rc can report, with its title and an example
//! program that triggers it. `docs/diagnostics.md` is generated from this table (a test fails when
//! the file is stale) and another test checks that each example of a parse or checker code really
//! produces its code.
//!
//! How to add a code: add one line to the `codes!` invocation below, in the block of its phase
//! (`E00xx` parse, `E01xx` names, `E02xx` types, `E03xx` scopes, `E04xx` vocabulary, `E05xx`
//! grounding, `E06xx` verification, `E07xx` planning), with a fresh number, a `Severity`, a title
//! that completes "error: ...", and a small example program. Never renumber or reuse a code:
//! users and tools match on them. Then regenerate the docs with
//! `UPDATE_DOCS=1 cargo test -p m2rc-tests --test it docs::`. An example of a code from `E0500`
//! on runs on the built-in demo house (the doc shows what `m2rc compile --map demo` prints).

use super::Severity;
use serde::{Serialize, Serializer};

macro_rules! codes {
    ($( $variant:ident = $id:literal, $sev:ident, $title:literal, $example:literal; )*) => {
        /// A stable diagnostic code; see the module docs for how to add one.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Code { $( $variant, )* }

        impl Code {
            /// Every code, in registry (numeric) order.
            pub const ALL: &'static [Code] = &[ $( Code::$variant, )* ];

            /// `"E0101"`.
            pub fn id(self) -> &'static str {
                match self { $( Code::$variant => $id, )* }
            }

            fn info(self) -> CodeInfo {
                match self {
                    $( Code::$variant => CodeInfo {
                        id: $id,
                        severity: Severity::$sev,
                        title: $title,
                        example: $example,
                    }, )*
                }
            }
        }
    };
}

/// What the registry knows about a code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CodeInfo {
    pub id: &'static str,
    pub severity: Severity,
    pub title: &'static str,
    /// A small program that triggers the code (empty for codes that need a map or a plan).
    pub example: &'static str,
}

impl Code {
    pub fn from_id(id: &str) -> Option<Code> {
        Code::ALL.iter().copied().find(|c| c.id() == id)
    }

    pub fn default_severity(self) -> Severity {
        self.info().severity
    }

    pub fn title(self) -> &'static str {
        self.info().title
    }

    pub fn example(self) -> &'static str {
        self.info().example
    }

    pub fn registry() -> impl Iterator<Item = CodeInfo> {
        Code::ALL.iter().map(|c| c.info())
    }
}

impl Serialize for Code {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.id())
    }
}

impl std::fmt::Display for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id())
    }
}

codes! {
    // --- E00xx: parse (codes owned by m2rc_grammar::ParseErrorKind::code) ----------------------
    SyntaxError = "E0000", Error, "syntax error",
        "";
    InvalidToken = "E0001", Error, "invalid character",
        "route { go @ }";
    UnexpectedToken = "E0002", Error, "unexpected token",
        "route { go ) }";
    UnexpectedEof = "E0003", Error, "unexpected end of file",
        "route { go start }\nlet b =";
    ExtraToken = "E0004", Error, "extra input after the program",
        "";
    UnterminatedString = "E0005", Error, "unterminated string",
        "route { go objects(\"bed) }";
    BadNumber = "E0006", Error, "number out of range",
        "let k = 99999999999999999999999\nroute { go start }";
    UnknownUnit = "E0007", Error, "unknown unit",
        "route { go start { prefer clearance(3ft) } }";
    BadEscape = "E0008", Error, "unknown escape in string",
        "let s = \"a\\q\"\nroute { go start }";
    SingleQuotedString = "E0009", Error, "single-quoted string",
        "route { go objects('bed').only() }";
    Semicolon = "E0010", Error, "semicolon after a statement",
        "let b = objects(bed).only();\nroute { go b }";
    Walrus = "E0011", Error, "`:=` instead of `let ... =`",
        "b := objects(bed).only()\nroute { go b }";
    AssignInsteadOfEq = "E0012", Error, "`=` instead of `==`",
        "let r = rooms().where(r => objects(stool).in(r).count() = 2).only()\nroute { go r }";
    ForeignKeyword = "E0013", Error, "keyword from another language",
        "def b = objects(bed).only()\nroute { go b }";
    ForeignOperator = "E0014", Error, "operator from another language",
        "let r = rooms().where(r => r.contains(objects(bed)) && r.contains(objects(desk))).only()\nroute { go r }";
    UnclosedDelimiter = "E0015", Error, "unclosed delimiter",
        "route { go objects(bed).only( }";
    HashComment = "E0016", Error, "`#` comment",
        "# go to the bed\nroute { go objects(bed).only() }";
    StatementTooLong = "E0017", Error, "statement too long",
        "";
    MissingLet = "E0018", Error, "binding without `let`",
        "b = objects(bed).only()\nroute { go b }";

    // --- E01xx: names ---------------------------------------------------------------------------
    UnknownName = "E0101", Error, "unknown name",
        "let sofa1 = objects(sofa).only()\nroute { go sofa2 }";
    CategoryAsValue = "E0102", Error, "category name used as a place",
        "route { go bed }";
    UnknownFunction = "E0103", Error, "unknown function",
        "route { go objcts(bed).only() }";
    UnknownMethod = "E0104", Error, "unknown method",
        "route { go objects(bed).nearst() }";
    WrongReceiver = "E0105", Error, "method called on the wrong kind of value",
        "route { go objects(bed).only().nearest() }";
    DuplicateBinding = "E0106", Error, "name bound twice in the same scope",
        "let b = objects(bed).only()\nlet b = objects(sofa).only()\nroute { go b }";
    UnusedBinding = "E0107", Warning, "unused binding",
        "let b = objects(bed).only()\nroute { go start }";
    OutOfScope = "E0108", Error, "binding used outside its scope",
        "route {\n  go objects(bed).only() {\n    let s = objects(sofa).only()\n    prefer far(s)\n  }\n  go s\n}";
    UnknownNamedArgument = "E0109", Error, "unknown named argument",
        "route { go objects(chair).nearest(too: start) }";
    DuplicateArgument = "E0110", Error, "argument given twice",
        "route { go objects(chair).nearest(to: start, to: start) }";
    FunctionAsValue = "E0111", Error, "built-in function used without a call",
        "route { go objects(chair).in(rooms.nearest()).nearest() }";
    RebindBuiltin = "E0112", Error, "built-in constant rebound",
        "let start = objects(bed).only()\nroute { go start }";
    MethodAsFunction = "E0113", Error, "method called as a function",
        "route { go nearest(objects(chair)) }";
    FunctionAsMethod = "E0114", Error, "function called as a method",
        "route { go objects(chair).center() }";

    // --- E02xx: types ---------------------------------------------------------------------------
    TypeMismatch = "E0201", Error, "mismatched types",
        "route { go objects(bed).only() { prefer near(2) } }";
    SetWhereSingle = "E0202", Error, "a set where a single value is expected",
        "route { go area_near(objects(bed)) }";
    NumberWhereDistance = "E0203", Error, "number without a unit where a distance is expected",
        "route { go objects(bed).only() { prefer clearance(0.5) } }";
    StringLiteral = "E0204", Error, "string literal where a name is expected",
        "route { go objects(\"bed\").only() }";
    TooManyArguments = "E0205", Error, "too many arguments",
        "route { go objects(bed, sofa).only() }";
    MissingArgument = "E0206", Error, "missing argument",
        "route { go start { prefer closer(objects(bed)) } }";
    PositionalAfterNamed = "E0207", Error, "positional argument after a named one",
        "route { go objects(chair).kth_nearest(to: start, 2) }";
    UnexpectedLambda = "E0208", Error, "lambda where no function is expected",
        "let f = x => x\nroute { go start }";
    LambdaBody = "E0209", Error, "lambda body has the wrong type",
        "route { go rooms().where(r => r.area()).only() }";
    IncomparableTypes = "E0210", Error, "comparison of incompatible types",
        "route { go rooms().where(r => r.area() < 2m).only() }";
    IfBranchesDiffer = "E0211", Error, "`if` branches have different types",
        "route { go if objects(tv_stand).exists() { objects(tv_stand).only() } else { rooms(kitchen) } }";
    ConditionNotBool = "E0212", Error, "condition is not a Bool",
        "route { go if objects(bed).count() { start } else { start } }";
    ForOverNonSet = "E0213", Error, "`for` over something that is not a set",
        "route { for r in rooms(bedroom).only() { go r } }";
    OperatorTypes = "E0214", Error, "operator applied to the wrong types",
        "let n = objects(bed) + 1\nroute { go start }";
    UnionMismatch = "E0215", Error, "union of a category and a set",
        "route { go (objects(bed) | sofa).nearest() }";
    ArgumentOutOfRange = "E0216", Error, "argument out of range",
        "route { go objects(chair).kth_nearest(0) { prefer clearance(-5m) } }";

    // --- E03xx: scopes and route structure ------------------------------------------------------
    MissingRoute = "E0301", Error, "missing `route` block",
        "let b = objects(bed).only()";
    MultipleRoutes = "E0302", Error, "more than one `route` block",
        "route { go start }\nroute { go start }";
    EmptyRoute = "E0303", Error, "route without a stage",
        "route { }";
    PassOutsideStage = "E0304", Error, "`pass` outside a stage",
        "route {\n  go objects(bed).only()\n  pass rooms(kitchen).only()\n}";
    DuringInsideStage = "E0305", Error, "`during` inside a stage",
        "route {\n  go objects(bed).only() as first {\n    prefer far(objects(sofa)) during first\n  }\n}";
    UnknownStage = "E0306", Error, "unknown stage name",
        "route {\n  go objects(bed).only() as bed_stage\n  prefer far(objects(sofa)) during bedstage\n}";
    DuplicateStage = "E0307", Error, "stage name used twice",
        "route {\n  go objects(bed).only() as a\n  go objects(sofa).only() as a\n}";
    WithinNotPlace = "E0308", Error, "`within` needs a place",
        "route { go start { prefer far(objects(sofa)) within 2m } }";
    PreferNotPreference = "E0309", Error, "`prefer` needs a preference",
        "route { go start { prefer objects(sofa).only() } }";
    AvoidPreference = "E0310", Error, "a preference after `avoid` or `pass`",
        "route { go start { avoid near(objects(sofa)) } }";
    GoTargetNotPlace = "E0311", Error, "`go` target is not a place",
        "route { go 3 }";
    DuplicateScope = "E0312", Error, "scope given twice",
        "route { go start { prefer far(objects(sofa)) within start.room() within start.room() } }";
    StagesOutOfOrder = "E0313", Error, "stages listed out of route order",
        "route {\n  go objects(bed).only() as a\n  go objects(sofa).only() as b\n  prefer far(objects(desk)) during b, a\n}";
    HereOutsideStage = "E0314", Error, "`here` in a route-wide constraint",
        "route {\n  go objects(bed).only()\n  avoid here.room()\n}";
    ConstraintNotPlace = "E0315", Error, "`pass` or `avoid` needs a place",
        "route { go start { avoid 2m } }";

    // --- E04xx: categories and vocabulary -------------------------------------------------------
    UnknownCategory = "E0401", Error, "unknown category",
        "route { go objects(chiar).nearest() }";
    RoomCategoryForObjects = "E0402", Error, "room category where an object category is expected",
        "route { go objects(kitchen).nearest() }";
    ObjectCategoryForRooms = "E0403", Error, "object category where a room category is expected",
        "route { go rooms(bed).nearest() }";
    CategoryNotInMap = "E0404", Error, "category not present in this map",
        "";
    AmbiguousCategory = "E0405", Error, "ambiguous category word",
        "route { go objects(table).nearest() }";
    SynonymResolved = "E0406", Warning, "category synonym",
        "route { go objects(tv).nearest() }";

    EmptySelection = "E0501", Error, "selection has no candidate on this map",
        "let can = objects(garbage_can).in(rooms(bathroom).smallest()).only()\nroute { go can }";
    AmbiguousSelection = "E0502", Error, "selection has several candidates on this map",
        "";
    EmptyRanking = "E0503", Error, "ranking of an empty selection",
        "";
    OrdinalOutOfRange = "E0504", Error, "ordinal out of range",
        "";
    Unreachable = "E0505", Error, "no traversable path between places",
        "";
    EmptyPlace = "E0506", Error, "place covers no cell of the map",
        "";
    RoutePlaceUndefined = "E0507", Error, "route-dependent place undefined on this route",
        "";
    NoRoom = "E0508", Error, "place lies in no room",
        "";
    NoStart = "E0509", Error, "no usable start position",
        "";
    EmptyConstraint = "E0510", Warning, "constraint matches nothing on this map",
        "";
    StageNotOnMap = "E0511", Warning, "stage not produced on this map",
        "";
    EvalUnsupported = "E0512", Error, "expression cannot be evaluated",
        "";
    StartMoved = "E0513", Warning, "start moved to the nearest free cell",
        "";

    NoStages = "E0601", Error, "route has no stage on this map",
        "";
    EmptyReference = "E0602", Error, "reference has no cells",
        "";
    TargetUnreachable = "E0603", Error, "target cannot be reached",
        "";
    StartForbidden = "E0604", Error, "start lies in an avoided region",
        "";
    TargetForbidden = "E0605", Error, "target lies entirely in an avoided region",
        "";
    ScopeMismatch = "E0606", Warning, "spatial scope does not meet the constraint",
        "";
    RelationRooms = "E0607", Warning, "relative preference across rooms",
        "";
    MalformedIr = "E0608", Error, "malformed RouteIR",
        "";

    // --- E07xx: planning (raised by m2rc_planner::PlanFailure::code) --------------------------
    StartBlocked = "E0701", Error, "start position is not traversable",
        "";
    StartInAvoid = "E0702", Error, "start lies inside an active avoid region",
        "";
    PlanTargetEmpty = "E0703", Error, "stage target covers no traversable cell",
        "";
    GoalBlocked = "E0704", Error, "stage target is covered by avoid regions",
        "";
    PlanUnreachable = "E0705", Error, "stage target is unreachable",
        "";
    UnreachableUnderAvoids = "E0706", Error, "stage target is unreachable under the active avoids",
        "let small = rooms(bedroom).smallest()\nroute {\n  go objects(bed).in(small).only()\n  avoid rooms(kitchen).only()\n}";
    BudgetExceeded = "E0707", Error, "search budget exhausted",
        "";
    InvalidPlanProblem = "E0708", Error, "invalid planning problem",
        "";

    // --- E08xx: the LTL backend (compiler::ltl, planner::product) ----------------------------
    LtlSyntax = "E0801", Error, "malformed LTL formula",
        "let sofa = objects(sofa).only()\nroute ltl \"F & sofa\" {}";
    LtlUnsupported = "E0802", Error, "unsupported operator in an LTL formula",
        "let sofa = objects(sofa).only()\nroute ltl \"F (sofa S sofa)\" {}";
    LtlUnbalanced = "E0803", Error, "unbalanced parentheses in an LTL formula",
        "let sofa = objects(sofa).only()\nroute ltl \"F (sofa\" {}";
    LtlUnknownAtom = "E0804", Error, "unknown atom in an LTL formula",
        "";
    LtlNotPlace = "E0805", Error, "LTL atom is not a place",
        "let n = objects(bed).count()\nroute ltl \"F n\" {}";
    LtlInfiniteIdiom = "E0806", Error, "LTL formula has no meaning on a finite route",
        "let sofa = objects(sofa).only()\nroute ltl \"G F sofa\" {}";
    LtlUnsatisfiable = "E0807", Error, "LTL formula is unsatisfiable",
        "let sofa = objects(sofa).only()\nroute ltl \"F sofa & G !sofa\" {}";
    LtlNoRoute = "E0808", Error, "no route on this map satisfies the LTL formula",
        "let kitchen = rooms(kitchen).only()\nlet fridge = objects(fridge).only()\nroute ltl \"F fridge & G !kitchen\" {}";
    LtlDropped = "E0809", Warning, "constraint ignored by the LTL planner",
        "let bed = objects(bed).only()\nroute ltl \"F bed\" {\n  prefer near(objects(sofa).only())\n}";
    LtlTooLarge = "E0810", Error, "LTL automaton too large",
        "";
    LtlNextStep = "E0811", Warning, "`X` counts grid cells, not places",
        "let sofa = objects(sofa).only()\nroute ltl \"X sofa\" {}";
    LtlMixedRoute = "E0812", Error, "`go` stage in an LTL route",
        "let sofa = objects(sofa).only()\nroute ltl \"F sofa\" {\n  go sofa\n}";

    // --- E09xx: JSON groundings (compiler::intent; the Schema and catalog-id variants) ------
    GraphNotJson = "E0901", Error, "reply is not a JSON object",
        "";
    GraphShape = "E0902", Error, "malformed grounding JSON",
        "";
    GraphUnknownOperator = "E0903", Error, "unknown operator in an intent graph",
        "";
    CatalogUnknownId = "E0904", Error, "id not in the scene catalog",
        "";
    CatalogArity = "E0905", Error, "wrong number of ids for a constraint",
        "";
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_unique_ordered_and_well_formed() {
        let ids: Vec<&str> = Code::ALL.iter().map(|c| c.id()).collect();
        assert!(
            ids.windows(2).all(|w| w[0] < w[1]),
            "codes must be listed in numeric order"
        );
        for id in ids {
            assert!(
                id.len() == 5 && id.starts_with('E') && id[1..].chars().all(|c| c.is_ascii_digit())
            );
            assert_eq!(Code::from_id(id).map(Code::id), Some(id));
        }
    }
}
