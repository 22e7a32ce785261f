//! The scene of a problem: its bodies and its contact pairs as two lists, whichever way the
//! problem holds them (one body with a `[contact]` table, two bodies in one pair, or the
//! `[[contact]]` tables of several pairs).
//!
//! A [`Problem`] still stores a scene in one of three shapes (the first body with `contact`
//! and `obstacles`; `second_body`; `multibody`). Code that only needs "every body" and "every
//! pair" reads them through [`Problem::bodies`] and [`Problem::pairs`], so that it treats the
//! shapes alike; the shapes themselves are what the contact core replaces next
//! (docs/dev/contact_core.md).

use super::{ContactSpec, Obstacle, Problem};

/// One contact pair of a scene, borrowed from its problem: the edge of `body` carrying the
/// candidates and its target (an edge of `target_body`, rigid obstacles or a rigid line).
#[derive(Clone, Copy, Debug)]
pub struct Pair<'a> {
    /// The body carrying the candidates, numbered as [`Problem::body`].
    pub body: usize,
    /// The contact edge of `body`, its target and its parameters.
    pub spec: &'a ContactSpec,
    /// The target body for [`super::ContactTarget::Body`] (`None` for a rigid target).
    pub target_body: Option<usize>,
    /// The obstacles of [`super::ContactTarget::Obstacles`] (empty otherwise).
    pub obstacles: &'a [Obstacle],
}

impl Problem {
    /// Every body of the scene, the first (this problem) first, numbered as [`Problem::body`].
    pub fn bodies(&self) -> impl Iterator<Item = &Problem> {
        (0..self.body_count()).filter_map(|k| self.body(k))
    }

    /// Every contact pair of the scene, in file order: the one pair of a `[contact]` table
    /// (against the second body when there is one), or the pairs of the `[[contact]]` tables;
    /// empty without contact.
    pub fn pairs(&self) -> Vec<Pair<'_>> {
        if let Some(several) = &self.multibody {
            return several
                .pairs
                .iter()
                .map(|p| Pair {
                    body: p.body,
                    spec: &p.spec,
                    target_body: p.target_body,
                    obstacles: &p.obstacles,
                })
                .collect();
        }
        self.contact
            .iter()
            .map(|spec| Pair {
                body: 0,
                spec,
                target_body: self.second_body.as_ref().map(|_| 1),
                obstacles: &self.obstacles,
            })
            .collect()
    }

    /// This body with `second` as the other body of its one contact pair (`contact`, whose
    /// target is an edge of `second`): a two-body scene built in code instead of read from a
    /// file.
    #[must_use]
    pub fn with_second_body(mut self, second: Problem) -> Self {
        self.second_body = Some(Box::new(second));
        self
    }

    /// Whether the scene holds more than one body or more than one contact pair (the
    /// `[[contact]]` tables of `multibody`), as opposed to one body, or two bodies in one pair.
    pub fn is_scene_of_pairs(&self) -> bool {
        self.multibody.is_some()
    }
}

#[cfg(test)]
mod tests {
    use crate::problem::{ContactTarget, Problem};

    fn shipped(name: &str) -> Problem {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems").join(name);
        Problem::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    /// `(body, target_body)` of every pair.
    fn ends(p: &Problem) -> Vec<(usize, Option<usize>)> {
        p.pairs().iter().map(|q| (q.body, q.target_body)).collect()
    }

    #[test]
    fn one_body_without_contact_has_no_pair() {
        let p = shipped("cantilever.toml");
        assert_eq!(p.bodies().count(), 1);
        assert!(p.pairs().is_empty());
    }

    #[test]
    fn one_body_on_a_rigid_line_is_one_pair_of_body_zero() {
        let p = shipped("beam_on_foundation.toml");
        assert_eq!(p.bodies().count(), 1);
        assert_eq!(ends(&p), [(0, None)]);
        assert!(matches!(p.pairs()[0].spec.target, ContactTarget::Rigid { .. }));
    }

    #[test]
    fn two_bodies_are_one_pair_against_body_one() {
        let p = shipped("two_blocks.toml");
        let names: Vec<&str> = p.bodies().map(|b| b.name.as_str()).collect();
        assert_eq!(names.len(), 2);
        assert_eq!(names[1], p.second_body.as_ref().unwrap().name);
        assert_eq!(ends(&p), [(0, Some(1))]);
    }

    #[test]
    fn a_stack_lists_its_bodies_and_pairs_in_file_order() {
        let p = shipped("three_block_stack.toml");
        assert_eq!(p.bodies().count(), 3);
        let several = p.multibody.as_ref().unwrap();
        let expected: Vec<_> = several.pairs.iter().map(|q| (q.body, q.target_body)).collect();
        assert_eq!(ends(&p), expected);
        assert_eq!(expected.len(), 2);
        assert!(p.is_scene_of_pairs());
    }
}
