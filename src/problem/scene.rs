//! The scene of a problem: its bodies and its contact pairs as two lists.
//!
//! A [`Problem`] is the first body and the scene: [`Problem::others`] holds the other bodies,
//! [`Problem::contact_pairs`] every pair, whatever the file said (one body with a `[contact]`
//! table, two bodies in one pair, or `[[contact]]` tables). Code that treats the pairs alike
//! reads [`Problem::pairs`]; the routes that still differ between one pair of the first body
//! (one body on a rigid target, or two bodies in one pair) and a scene of several pairs ask
//! [`Problem::is_scene_of_pairs`], and read the one pair through [`Problem::contact`],
//! [`Problem::obstacles`] and [`Problem::second_body`] or the scene through
//! [`Problem::multibody`].

use super::{ContactPair, ContactSpec, ContactTarget, Multibody, Obstacle, Problem};

impl Problem {
    /// Every body of the scene, the first (this problem) first, numbered as [`Problem::body`].
    pub fn bodies(&self) -> impl Iterator<Item = &Problem> {
        std::iter::once(self).chain(&self.others)
    }

    /// Every contact pair of the scene, in file order; empty without contact.
    pub fn pairs(&self) -> &[ContactPair] {
        &self.contact_pairs
    }

    /// Whether the scene holds more than two bodies, more than one contact pair, or a pair
    /// that is not the first body's edge against the second body or a rigid target — the
    /// scenes solved as several pairs, as opposed to one body (with or without contact) or
    /// two bodies in one pair of the first body.
    pub fn is_scene_of_pairs(&self) -> bool {
        !(self.others.len() <= 1
            && self.contact_pairs.len() <= 1
            && self
                .contact_pairs
                .iter()
                .all(|p| p.body == 0 && p.target_body.is_none_or(|t| t == 1)))
    }

    /// The contact of the first body's one pair (`None` without contact and for a scene of
    /// pairs, [`Problem::is_scene_of_pairs`]).
    pub fn contact(&self) -> Option<&ContactSpec> {
        self.one_pair().map(|p| &p.spec)
    }

    /// The contact of the first body's one pair, mutable (as [`Problem::contact`]).
    pub fn contact_mut(&mut self) -> Option<&mut ContactSpec> {
        if self.is_scene_of_pairs() {
            return None;
        }
        self.contact_pairs.first_mut().map(|p| &mut p.spec)
    }

    /// The rigid obstacles of the first body's one pair (empty for another target, without
    /// contact and for a scene of pairs).
    pub fn obstacles(&self) -> &[Obstacle] {
        self.one_pair().map_or(&[], |p| &p.obstacles)
    }

    /// The second body of a two-body scene of one pair (`None` for one body and for a scene
    /// of pairs).
    pub fn second_body(&self) -> Option<&Problem> {
        if self.is_scene_of_pairs() {
            return None;
        }
        self.others.first()
    }

    /// The bodies and pairs of a scene of pairs (`None` unless
    /// [`Problem::is_scene_of_pairs`]).
    pub fn multibody(&self) -> Option<Multibody<'_>> {
        self.is_scene_of_pairs()
            .then_some(Multibody { bodies: &self.others, pairs: &self.contact_pairs })
    }

    /// Gives the first body one contact pair, `spec` (against the second body's edge when
    /// its target is [`ContactTarget::Body`]), replacing any pairs: a scene built in code.
    pub fn set_contact(&mut self, spec: ContactSpec) {
        let target_body = matches!(spec.target, ContactTarget::Body { .. }).then_some(1);
        self.contact_pairs =
            vec![ContactPair { body: 0, spec, target_body, obstacles: Vec::new() }];
    }

    /// This body with `second` as the other body of its one contact pair (`contact`, whose
    /// target is an edge of `second`): a two-body scene built in code instead of read from a
    /// file.
    #[must_use]
    pub fn with_second_body(mut self, second: Problem) -> Self {
        self.others = vec![second];
        self
    }

    /// The one pair of the first body, unless the scene is a scene of pairs.
    fn one_pair(&self) -> Option<&ContactPair> {
        if self.is_scene_of_pairs() {
            return None;
        }
        self.contact_pairs.first()
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
        assert_eq!(names[1], p.second_body().unwrap().name);
        assert_eq!(ends(&p), [(0, Some(1))]);
    }

    #[test]
    fn a_stack_lists_its_bodies_and_pairs_in_file_order() {
        let p = shipped("three_block_stack.toml");
        assert_eq!(p.bodies().count(), 3);
        let several = p.multibody().unwrap();
        let expected: Vec<_> = several.pairs.iter().map(|q| (q.body, q.target_body)).collect();
        assert_eq!(ends(&p), expected);
        assert_eq!(expected.len(), 2);
        assert!(p.is_scene_of_pairs());
    }
}
