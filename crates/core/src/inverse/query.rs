//! The queries of a map that may fold through its atlas, in bounded work: the plan that sizes the
//! atlas and each query's work budget, the walk to the pieces whose image holds the point, and
//! Newton's polish of their seeds on the net.

use alloc::boxed::Box;
use alloc::vec::Vec;
use core::sync::atomic::Ordering;

use super::atlas::{Atlas, AtlasBudget, Share};
use super::newton::{ROOT_RESIDUAL, ROUNDING_RESIDUAL, SETTLED_STEP};
use super::{
    Eval, Forward, InverseMap, MAX_ATLAS_ROOTS, MAX_PIECE_SEEDS, MERGE, QueryStats, clamp_unit,
    inside_closed, max_abs_diff, solve_jac,
};

impl<const D: usize> InverseMap<D> {
    /// Says that about `queries` queries are coming (a grid, a file of points), before the first:
    /// a map that may fold cuts its atlas (see the module documentation) for that much work,
    /// finer for more, and bounds each query's work so that all of them together stay within
    /// about a second however the net folds, and queries past the plan add little
    /// ([`QueryStats::exhausted`] says where a query ran out). The largest plan before the first
    /// query sets the atlas; the largest at a query sets its work.
    pub fn plan(&self, queries: usize) {
        self.planned.fetch_max(queries, Ordering::Relaxed);
    }

    /// [`InverseMap::plan`], and every query from now on may spend the plan's share of the work,
    /// whatever was spent before it, not the least once the plan's work is spent: the value at
    /// a point no longer depends on the queries made before it. A mesh whose blocks sample the
    /// points of a shared face each (on any thread, in any order) then sees one sign there, and
    /// stays closed where queries run out of their budget (two shuffled degree-16 volumes
    /// meshed at 16 left 45 open edges).
    pub fn fix_query_work(&self, queries: usize) {
        self.plan(queries);
        let work = AtlasBudget::query_work(
            self.planned.load(Ordering::Relaxed).max(1),
            0,
            self.shared(),
            self.tensor.coefs.len(),
        );
        self.fixed.store(work, Ordering::Relaxed);
    }

    /// Says that the map takes `share` of the command it serves (one leaf of a tree, one cell of
    /// a piecewise solid), before the plan and the first query: its atlas and its queries' work
    /// are that part of one map's (see [`Share`]).
    pub fn share(&self, share: Share) {
        let share = Share::new(share.reach, share.load);
        self.reach.store(share.reach.to_bits(), Ordering::Relaxed);
        self.load.store(share.load.to_bits(), Ordering::Relaxed);
    }

    /// The map's part of its command (see [`InverseMap::share`]): the whole where not said.
    #[must_use]
    pub fn shared(&self) -> Share {
        Share {
            reach: f64::from_bits(self.reach.load(Ordering::Relaxed)),
            load: f64::from_bits(self.load.load(Ordering::Relaxed)),
        }
    }

    /// How many queries so far ran out of their work budget (see [`QueryStats::exhausted`]): a
    /// drawing made of them may miss pieces where the net folds very many times over.
    #[must_use]
    pub fn exhausted(&self) -> usize {
        self.exhausted.load(Ordering::Relaxed)
    }

    /// The atlas of the map (see [`atlas`](super::atlas)), built on first use.
    fn atlas(&self) -> &Atlas<D> {
        self.atlas.get_or_init(|| {
            let queries = self.planned.load(Ordering::Relaxed);
            let budget =
                AtlasBudget::for_queries(D, self.tensor.coefs.len(), queries, self.shared());
            Box::new(Atlas::build(&self.tensor, budget))
        })
    }

    /// The number of pieces of the map's atlas and how many of them are certified injective
    /// (building the atlas if it was not yet).
    #[must_use]
    pub fn atlas_pieces(&self) -> (usize, usize) {
        let atlas = self.atlas();
        (atlas.len(), atlas.certified())
    }

    /// Every preimage of `p` through the atlas, in bounded work, with `S_ξ` there: the seeds of
    /// the pieces whose image holds `p`, each polished by Newton's method on the net.
    pub(super) fn atlas_roots<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        stats: &mut QueryStats,
    ) -> Vec<([f64; D], f64)> {
        let mut roots: Vec<([f64; D], f64)> = Vec::new();
        let cap = self.query_work();
        let points = self.tensor.coefs.len() as u64;
        self.atlas().pieces_at(p, |piece| {
            stats.atlas_pieces += 1;
            if stats.work >= cap {
                stats.exhausted = true;
                return;
            }
            let seeds = piece.seeds(p, MAX_PIECE_SEEDS, &mut stats.clip, &mut stats.work);
            for seed in seeds {
                // A seed at a preimage already found (a neighbour's, across their seam) is it.
                stats.work += roots.len() as u64;
                if roots.iter().any(|(r, _)| max_abs_diff(*r, seed) <= 1e-9) {
                    continue;
                }
                if stats.work >= cap || roots.len() >= MAX_ATLAS_ROOTS {
                    stats.exhausted = true;
                    return;
                }
                stats.atlas_solves += 1;
                let before = stats.newton_steps;
                let found = self.polish(net, p, seed, (piece.lo, piece.hi), stats);
                stats.work += u64::from(stats.newton_steps - before + 1) * points;
                let Some((u, e)) = found else {
                    continue;
                };
                if roots.iter().all(|(r, _)| max_abs_diff(*r, u) > MERGE) {
                    roots.push((u, e.xi));
                }
                // A certified piece holds one preimage at most: once found there, done.
                let tol = 1e-9;
                let here = (0..D).all(|a| u[a] >= piece.lo[a] - tol && u[a] <= piece.hi[a] + tol);
                if piece.certified && here {
                    return;
                }
            }
        });
        if stats.exhausted {
            self.exhausted.fetch_add(1, Ordering::Relaxed);
        }
        self.spent.fetch_add(stats.work, Ordering::Relaxed);
        roots
    }

    /// The work the next query through the atlas may spend (see [`AtlasBudget::query_work`]).
    pub(super) fn query_work(&self) -> u64 {
        let fixed = self.fixed.load(Ordering::Relaxed);
        if fixed > 0 {
            return fixed;
        }
        AtlasBudget::query_work(
            self.planned.load(Ordering::Relaxed),
            self.spent.load(Ordering::Relaxed),
            self.shared(),
            self.tensor.coefs.len(),
        )
    }

    /// Newton's method for `S(u) = p` from an atlas seed in the piece `[lo, hi]`: the root in the
    /// closed unit box with the evaluation there, or `None` when it diverges, stalls (its residual
    /// grows again), or wanders more than a piece's width away (a root there is its own piece's to
    /// find).
    fn polish<F: Forward<D>>(
        &self,
        net: &F,
        p: [f64; D],
        mut u: [f64; D],
        (lo, hi): ([f64; D], [f64; D]),
        stats: &mut QueryStats,
    ) -> Option<([f64; D], Eval<D>)> {
        let tight = self.scale.max(f64::MIN_POSITIVE) * ROUNDING_RESIDUAL;
        let mut last = f64::INFINITY;
        let mut before = f64::INFINITY;
        for step in 0..12 {
            let e = net.forward(u);
            let r: [f64; D] = core::array::from_fn(|c| e.x[c] - p[c]);
            let res = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            // Near a root Newton's residual shrinks step by step (by a quarter at a fold's double
            // root, far more at a simple one); one that grows again is lost and given up early.
            if step >= 3 && res > before {
                return None;
            }
            before = res;
            if res <= tight || (last <= SETTLED_STEP && res <= self.scale * ROOT_RESIDUAL) {
                return inside_closed(u, 1e-12).then(|| {
                    let clamped = clamp_unit(u);
                    let e = if clamped == u {
                        e
                    } else {
                        net.forward(clamped)
                    };
                    (clamped, e)
                });
            }
            if last <= SETTLED_STEP {
                return None;
            }
            let delta = solve_jac(&e.jac, r)?;
            stats.newton_steps += 1;
            for c in 0..D {
                u[c] -= delta[c];
            }
            last = delta.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            let away = (0..D).any(|c| {
                let w = hi[c] - lo[c];
                !(u[c] >= lo[c] - w && u[c] <= hi[c] + w)
            });
            if away {
                return None;
            }
        }
        None
    }
}
