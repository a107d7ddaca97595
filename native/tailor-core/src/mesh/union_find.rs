//! Disjoint sets over node indices (path halving, union by size): which vertices and seam
//! points become one welded vertex (`weld`), which sewn vertices count as one (`quality`).

pub(crate) struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    pub fn new(n: usize) -> Self {
        UnionFind { parent: (0..n as u32).collect(), size: vec![1; n] }
    }

    /// Adds one singleton set; returns its index.
    pub fn push(&mut self) -> u32 {
        let i = self.parent.len() as u32;
        self.parent.push(i);
        self.size.push(1);
        i
    }

    pub fn len(&self) -> usize {
        self.parent.len()
    }

    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let p = self.parent[x as usize];
            self.parent[x as usize] = self.parent[p as usize];
            x = p;
        }
        x
    }

    pub fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return;
        }
        let (big, small) = if self.size[ra as usize] >= self.size[rb as usize] { (ra, rb) } else { (rb, ra) };
        self.parent[small as usize] = big;
        self.size[big as usize] += self.size[small as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_join_and_singletons_stay() {
        let mut uf = UnionFind::new(5);
        uf.union(0, 3);
        uf.union(3, 4);
        let extra = uf.push();
        assert_eq!(extra, 5);
        uf.union(5, 1);
        assert_eq!(uf.find(0), uf.find(4));
        assert_eq!(uf.find(1), uf.find(5));
        assert_ne!(uf.find(0), uf.find(1));
        assert_ne!(uf.find(2), uf.find(0));
        assert_eq!(uf.len(), 6);
    }
}
