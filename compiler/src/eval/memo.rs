//! Memoisation of sub-expressions inside lambdas, which keeps nested filters polynomial.
//!
//! Without it, `rooms().where(a => rooms().where(b => ... ).exists())` re-evaluates the inner
//! filter for every candidate of the outer one, so d nested filters over n rooms cost n^d.
//!
//! While a lambda-taking call (`where`, `sorted_by`, `max_by`, `min_by`) runs, nothing but lambda
//! parameters can change: the scopes outside them, `here`, the stage and the planned route are
//! fixed for the whole evaluation of that one expression. So within such a *window* the value of
//! a call or method expression depends only on the values of the lambda parameters free in it,
//! and is cached under (expression, those values). An expression free of lambda parameters (the
//! `objects(bed)` inside `o => o.near(objects(bed))`) is evaluated once per window.
//!
//! **Bound.** Each (expression, assignment of the lambda parameters free in it) is evaluated at
//! most once per window, so a program of size P over sets of at most n elements costs at most
//! P · n^(k+1) evaluations, where k is the largest number of enclosing lambda parameters any
//! one lambda body refers to. Chained nesting, where each body refers to its own parameter and
//! its parent's (`a => rooms().where(b => b.adjacent_to(a) and ...)`), has k = 1: O(P · n²),
//! whatever the depth. Only a body that genuinely relates k outer candidates at once pays n^k.
//!
//! Calls whose value depends on the route (`first_entered`, `doorway_leaving`, ...) record route
//! bindings as a side effect and are never cached.

use super::value::{PlaceVal, Value};
use m2rc_grammar::ast::{Expr, ExprKind};
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::rc::Rc;

/// Built-ins whose value is read off the route.
pub(crate) const ROUTE_DEPENDENT: &[&str] = &[
    "room_before_entering",
    "doorway_leaving",
    "doorway_entering",
    "first_entered",
    "kth_entered",
    "visited",
    "left_behind",
];

/// What an expression's value can depend on.
#[derive(Debug, Default)]
pub(super) struct FreeInfo {
    /// Names used in the expression and not bound by a lambda inside it.
    names: Vec<String>,
    route_dependent: bool,
}

/// The identity of a parameter's value, for cache keys.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum ParamKey {
    Object(u32),
    Room(u32),
    Region(u64),
    Other,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) struct Key {
    expr: usize,
    params: Vec<ParamKey>,
}

#[derive(Default)]
pub(super) struct Memo {
    /// Lambda parameters in scope, innermost last.
    pub params: Vec<String>,
    /// How many lambda-taking calls are running; the cache lives while this is non-zero.
    windows: usize,
    cache: HashMap<Key, Value>,
    free: HashMap<usize, Rc<FreeInfo>>,
    /// Lambda bodies shared between applications, by the address of the lambda's body.
    bodies: HashMap<usize, Rc<Expr>>,
}

fn addr(e: &Expr) -> usize {
    e as *const Expr as usize
}

impl Memo {
    pub fn active(&self) -> bool {
        self.windows > 0
    }

    pub fn open(&mut self) {
        self.windows += 1;
    }

    pub fn close(&mut self) {
        self.windows = self.windows.saturating_sub(1);
        if self.windows == 0 {
            self.cache.clear();
        }
    }

    pub fn get(&self, k: &Key) -> Option<Value> {
        self.cache.get(k).cloned()
    }

    pub fn insert(&mut self, k: Key, v: Value) {
        self.cache.insert(k, v);
    }

    pub fn lambda_body(&mut self, body: &Expr) -> Rc<Expr> {
        self.bodies
            .entry(addr(body))
            .or_insert_with(|| Rc::new(body.clone()))
            .clone()
    }

    pub fn free_info(&mut self, e: &Expr) -> Rc<FreeInfo> {
        if let Some(i) = self.free.get(&addr(e)) {
            return i.clone();
        }
        let mut info = FreeInfo::default();
        let add = |info: &mut FreeInfo, child: &FreeInfo, bound: Option<&str>| {
            info.route_dependent |= child.route_dependent;
            for n in &child.names {
                if Some(n.as_str()) != bound && !info.names.contains(n) {
                    info.names.push(n.clone());
                }
            }
        };
        match &e.kind {
            ExprKind::Name(id) => info.names.push(id.name.clone()),
            ExprKind::Call { func, args } => {
                info.route_dependent = ROUTE_DEPENDENT.contains(&func.name.as_str());
                for a in args {
                    let c = self.free_info(&a.value);
                    add(&mut info, &c, None);
                }
            }
            ExprKind::Method { receiver, args, .. } => {
                let c = self.free_info(receiver);
                add(&mut info, &c, None);
                for a in args {
                    let c = self.free_info(&a.value);
                    add(&mut info, &c, None);
                }
            }
            ExprKind::Lambda { param, body } => {
                let c = self.free_info(body);
                add(&mut info, &c, Some(&param.name));
            }
            ExprKind::Binary { lhs, rhs, .. } => {
                for x in [lhs, rhs] {
                    let c = self.free_info(x);
                    add(&mut info, &c, None);
                }
            }
            ExprKind::Unary { operand, .. } => {
                let c = self.free_info(operand);
                add(&mut info, &c, None);
            }
            ExprKind::If {
                cond,
                then,
                otherwise,
            } => {
                for x in [cond, then, otherwise] {
                    let c = self.free_info(x);
                    add(&mut info, &c, None);
                }
            }
            _ => {}
        }
        let info = Rc::new(info);
        self.free.insert(addr(e), info.clone());
        info
    }
}

impl super::Grounder<'_, '_> {
    /// The cache key of `e` in the current window, or `None` when `e` must not be cached.
    pub(super) fn memo_key(&self, e: &Expr, info: &FreeInfo) -> Option<Key> {
        if info.route_dependent {
            return None;
        }
        let mut params = Vec::new();
        for n in &info.names {
            if !self.memo.params.contains(n) {
                continue;
            }
            params.push(match self.lookup(n) {
                Some(Value::Place(PlaceVal::Object(id))) => ParamKey::Object(*id),
                Some(Value::Place(PlaceVal::Room(id))) => ParamKey::Room(*id),
                Some(Value::Place(PlaceVal::Region(r))) => {
                    let mut h = std::collections::hash_map::DefaultHasher::new();
                    r.cells.hash(&mut h);
                    ParamKey::Region(h.finish())
                }
                _ => ParamKey::Other,
            });
        }
        if params.contains(&ParamKey::Other) {
            return None;
        }
        Some(Key {
            expr: addr(e),
            params,
        })
    }
}
