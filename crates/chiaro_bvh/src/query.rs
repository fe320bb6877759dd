//! The ray queries every traversal answers the same way from the candidate hits it offers:
//! the nearest accepted hit, and whether any is accepted.

use crate::blas::Candidate;
use crate::ray::{Hit, Ray};

/// A structure that offers a ray's candidate hits ([`SceneBvh`](crate::SceneBvh) through its
/// TLAS, [`FlatBvh`](crate::FlatBvh) through its one tree).
pub(crate) trait CandidateHits {
    /// Offers `ray`'s candidate hits in `(t_min, t_max)` to `on_hit`, each nearer than the last
    /// one it accepted; true when `on_hit` stopped it. An invalid ray (see [`Ray::is_valid`]) or
    /// an empty interval offers none.
    fn offer(&self, ray: &Ray, on_hit: &mut impl FnMut(Hit) -> Candidate) -> bool;

    /// The nearest hit that `accept` takes.
    fn nearest_accepted(&self, ray: &Ray, accept: impl Fn(&Hit) -> bool) -> Option<Hit> {
        let mut best = None;
        self.offer(ray, &mut |hit| {
            if accept(&hit) {
                best = Some(hit);
                Candidate::Accept
            } else {
                Candidate::Reject
            }
        });
        best
    }

    /// Whether any hit that `accept` takes exists (stops at the first).
    fn any_accepted(&self, ray: &Ray, accept: impl Fn(&Hit) -> bool) -> bool {
        self.offer(ray, &mut |hit| {
            if accept(&hit) {
                Candidate::Stop
            } else {
                Candidate::Reject
            }
        })
    }
}
