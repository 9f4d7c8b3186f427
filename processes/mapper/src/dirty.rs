//! A set of cell indices without duplicates, allocated once for the whole grid.

/// Cells marked for some later work, each at most once; `clear` keeps the memory.
#[derive(Debug, Clone, Default)]
pub struct DirtySet {
    flags: Vec<bool>,
    list: Vec<u32>,
}

impl DirtySet {
    /// An empty set able to hold every cell of a `cell_count` grid without reallocating.
    pub fn new(cell_count: usize) -> Self {
        Self {
            flags: vec![false; cell_count],
            list: Vec::with_capacity(cell_count),
        }
    }

    /// Marks `index` (ignored if outside the grid or already marked).
    pub fn insert(&mut self, index: usize) {
        if let Some(flag) = self.flags.get_mut(index)
            && !*flag
        {
            *flag = true;
            self.list.push(index as u32);
        }
    }

    /// Marked cells in marking order.
    pub fn as_slice(&self) -> &[u32] {
        &self.list
    }

    /// Number of marked cells.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// True when nothing is marked.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Unmarks the first `count` cells in marking order (all if fewer), keeping the rest.
    pub fn remove_first(&mut self, count: usize) {
        let count = count.min(self.list.len());
        for &index in &self.list[..count] {
            self.flags[index as usize] = false;
        }
        self.list.drain(..count);
    }

    /// Unmarks everything.
    pub fn clear(&mut self) {
        for &index in &self.list {
            self.flags[index as usize] = false;
        }
        self.list.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marks_once_and_ignores_outside() {
        let mut set = DirtySet::new(4);
        set.insert(2);
        set.insert(2);
        set.insert(9);
        set.insert(0);
        assert_eq!(set.as_slice(), &[2, 0]);
        set.clear();
        assert!(set.is_empty());
        set.insert(2);
        assert_eq!(set.len(), 1);
        set.insert(3);
        set.insert(1);
        set.remove_first(2);
        assert_eq!(set.as_slice(), &[1]);
        set.insert(2);
        assert_eq!(set.as_slice(), &[1, 2]);
    }
}
