//! Disjoint sets (union–find) over `u32` ids, for connected components.

/// Union–find with path halving and union by size.
#[derive(Clone, Debug)]
pub struct DisjointSets {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl DisjointSets {
    /// `n` singleton sets.
    pub fn new(n: usize) -> Self {
        DisjointSets {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    /// Representative of the set holding `x`.
    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let gp = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = gp;
            x = gp;
        }
        x
    }

    /// Merges the sets of `a` and `b`; returns false if they were one set.
    pub fn union(&mut self, a: u32, b: u32) -> bool {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return false;
        }
        if self.size[a as usize] < self.size[b as usize] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b as usize] = a;
        self.size[a as usize] += self.size[b as usize];
        true
    }

    /// Dense labels `0..k` for the sets, numbered by their smallest member;
    /// returns `(label of every id, k)`.
    pub fn labels(&mut self) -> (Vec<u32>, usize) {
        let n = self.parent.len();
        let mut label = vec![u32::MAX; n];
        let mut out = vec![0u32; n];
        let mut k = 0u32;
        for x in 0..n as u32 {
            let r = self.find(x) as usize;
            if label[r] == u32::MAX {
                label[r] = k;
                k += 1;
            }
            out[x as usize] = label[r];
        }
        (out, k as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_follow_smallest_member() {
        let mut d = DisjointSets::new(5);
        d.union(3, 1);
        d.union(4, 2);
        assert!(!d.union(1, 3));
        assert_eq!(d.labels(), (vec![0, 1, 2, 1, 2], 3));
    }
}
