//! Region-code merging (Yang et al. 2002, section 1.4): codes that differ in one bit merge into
//! one class with that bit masked (010 + 011 = 01X), by a binary tree whose levels are the bits,
//! the bit whose most common value is most frequent at the top, so that fewer classes (passes,
//! transfer-function tables) remain.

use std::collections::BTreeMap;

use super::{Effect, Scene};

/// A set of codes: those with `code & mask == value & mask` (bits outside `mask` are X).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Class {
    pub value: u8,
    pub mask: u8,
}

impl Class {
    pub fn matches(&self, code: u8) -> bool {
        code & self.mask == self.value & self.mask
    }

    /// The paper's notation: body 0 rightmost, X for masked bits.
    pub fn pattern(&self, bits: usize) -> String {
        (0..bits.max(1))
            .rev()
            .map(|i| match (self.mask >> i & 1, self.value >> i & 1) {
                (0, _) => 'X',
                (_, 1) => '1',
                _ => '0',
            })
            .collect()
    }
}

/// The paper's tree order: bits sorted by how often their most common value occurs, most first;
/// ties go to the higher bit.
pub fn frequency_order(codes: &[u8], bits: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..bits).collect();
    let score = |b: usize| {
        let ones = codes.iter().filter(|&&c| c >> b & 1 == 1).count();
        ones.max(codes.len() - ones)
    };
    order.sort_by(|&a, &b| score(b).cmp(&score(a)).then(b.cmp(&a)));
    order
}

/// Merges with the tree whose levels are `order` (top first). At every node, a sub-pattern found
/// under both children merges into one with this level's bit masked. The classes are disjoint and
/// cover exactly the given codes.
pub fn merge_with_order(codes: &[u8], order: &[usize]) -> Vec<Class> {
    let mut c: Vec<u8> = codes.to_vec();
    c.sort_unstable();
    c.dedup();
    let mut out = node(&c, order);
    out.sort();
    out
}

fn node(codes: &[u8], order: &[usize]) -> Vec<Class> {
    if codes.is_empty() {
        return Vec::new();
    }
    let Some((&b, rest)) = order.split_first() else {
        return vec![Class { value: 0, mask: 0 }];
    };
    let (zeros, ones): (Vec<u8>, Vec<u8>) = codes.iter().partition(|&&c| c >> b & 1 == 0);
    let left = node(&zeros, rest);
    let right = node(&ones, rest);
    let bit = 1u8 << b;
    let mut out = Vec::with_capacity(left.len() + right.len());
    for p in &left {
        if right.contains(p) {
            out.push(*p);
        } else {
            out.push(Class {
                value: p.value,
                mask: p.mask | bit,
            });
        }
    }
    for p in &right {
        if !left.contains(p) {
            out.push(Class {
                value: p.value | bit,
                mask: p.mask | bit,
            });
        }
    }
    out
}

/// The paper's merge (frequency-ordered tree); with up to 6 bodies every tree order is tried as
/// well and the fewest classes kept (the paper's order wins ties), which also settles the
/// frequency ties the paper leaves open.
pub fn merge(codes: &[u8], bits: usize) -> Vec<Class> {
    let order = frequency_order(codes, bits);
    let mut best = merge_with_order(codes, &order);
    if bits <= 6 && best.len() > 1 {
        let mut perm: Vec<usize> = (0..bits).collect();
        permute(&mut perm, 0, &mut |o| {
            let m = merge_with_order(codes, o);
            if m.len() < best.len() {
                best = m;
            }
        });
    }
    best
}

fn permute(v: &mut Vec<usize>, k: usize, f: &mut dyn FnMut(&[usize])) {
    if k == v.len() {
        f(v);
        return;
    }
    for i in k..v.len() {
        v.swap(k, i);
        permute(v, k + 1, f);
        v.swap(k, i);
    }
}

/// Codes grouped by what applies to them, each group merged: one pass per class of a drawn
/// effect (cut classes need no pass).
#[derive(Clone, Debug, PartialEq)]
pub struct Merged {
    pub groups: Vec<(Effect, Vec<Class>)>,
}

impl Merged {
    /// Classes that must be drawn (one table and pass each).
    pub fn drawn_classes(&self) -> usize {
        self.groups
            .iter()
            .filter(|(e, _)| *e != Effect::Cut)
            .map(|(_, c)| c.len())
            .sum()
    }

    /// The class index (in drawing order) and effect for a code, if it is drawn.
    pub fn class_of(&self, code: u8) -> Option<(usize, Effect)> {
        let mut i = 0;
        for (e, classes) in &self.groups {
            if *e == Effect::Cut {
                continue;
            }
            for c in classes {
                if c.matches(code) {
                    return Some((i, *e));
                }
                i += 1;
            }
        }
        None
    }
}

/// Merges the codes present, within groups of equal effect under the scene's rule.
pub fn merge_scene(scene: &Scene, codes: &[u8]) -> Merged {
    let mut by: BTreeMap<Effect, Vec<u8>> = BTreeMap::new();
    for &c in codes {
        by.entry(scene.effect(c)).or_default().push(c);
    }
    Merged {
        groups: by
            .into_iter()
            .map(|(e, cs)| (e, merge(&cs, scene.bodies.len())))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn patterns(c: &[Class], bits: usize) -> Vec<String> {
        let mut v: Vec<String> = c.iter().map(|c| c.pattern(bits)).collect();
        v.sort();
        v
    }

    #[test]
    fn papers_example_gives_x1x_and_x01() {
        let codes = [0b010, 0b011, 0b001, 0b110, 0b111, 0b101];
        // The paper's order: middle bit first, then the last, then the first.
        assert_eq!(frequency_order(&codes, 3), vec![1, 0, 2]);
        let m = merge_with_order(&codes, &frequency_order(&codes, 3));
        assert_eq!(patterns(&m, 3), vec!["X01", "X1X"]);
        assert_eq!(patterns(&merge(&codes, 3), 3), vec!["X01", "X1X"]);
        // Pairing 010+011 and 111+101 first strands 001 and 110: four classes, the paper's bad
        // order; no tree order does worse than two here.
        let greedy = [
            Class {
                value: 0b010,
                mask: 0b110,
            },
            Class {
                value: 0b101,
                mask: 0b101,
            },
            Class {
                value: 0b001,
                mask: 0b111,
            },
            Class {
                value: 0b110,
                mask: 0b111,
            },
        ];
        assert_eq!(greedy.len(), 4);
        for c in codes {
            assert_eq!(greedy.iter().filter(|g| g.matches(c)).count(), 1);
        }
        let mut perm = vec![0, 1, 2];
        permute(&mut perm, 0, &mut |o| {
            assert!(merge_with_order(&codes, o).len() >= 2)
        });
        // 010, 011, 110, 111 -> X1X (the paper's second example).
        let m = merge(&[0b010, 0b011, 0b110, 0b111], 3);
        assert_eq!(patterns(&m, 3), vec!["X1X"]);
        // 010 and 001 cannot merge.
        assert_eq!(merge(&[0b010, 0b001], 3).len(), 2);
        // All seven non-zero codes of three cuts: no single class covers them without 000.
        let all: Vec<u8> = (0..8).collect();
        assert_eq!(patterns(&merge(&all, 3), 3), vec!["XXX"]);
    }

    #[test]
    fn classes_cover_exactly_and_disjointly() {
        let mut seed = 99u64;
        for _ in 0..300 {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            let bits = 1 + (seed >> 60) as usize % 5;
            let set = (seed >> 20) as u32;
            let codes: Vec<u8> = (0..(1u32 << bits))
                .filter(|c| set >> c & 1 == 1)
                .map(|c| c as u8)
                .collect();
            let m = merge(&codes, bits);
            for c in 0..(1u32 << bits) as u8 {
                let n = m.iter().filter(|k| k.matches(c)).count();
                assert_eq!(
                    n,
                    usize::from(codes.contains(&c)),
                    "codes {codes:?} classes {m:?} code {c}"
                );
            }
        }
    }
}
