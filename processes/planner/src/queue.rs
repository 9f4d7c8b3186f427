//! The D* Lite priority queue: a binary heap with lazy deletion and a per-vertex stored key.
//!
//! Each vertex has at most one *live* key, stored in a dense array. The heap may also hold
//! stale entries (superseded or removed keys); they are skipped when they reach the top and
//! purged when they outnumber live entries. This gives D* Lite's `Insert`, `Update`,
//! `Remove`, `Top` and `TopKey` with `O(log n)` amortised cost and an `O(1)` membership test.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::cost::{Cost, INFINITE_COST};

/// A D* Lite key `[k1; k2]`, ordered lexicographically.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Key {
    /// `min(g, rhs) + h(start, s) + k_m`.
    pub primary: Cost,
    /// `min(g, rhs)`.
    pub secondary: Cost,
}

impl Key {
    /// The key larger than every finite key: the `TopKey` of an empty queue.
    pub const INFINITE: Key = Key {
        primary: INFINITE_COST,
        secondary: INFINITE_COST,
    };
}

/// Marker for "not in the queue"; a queued vertex is inconsistent, so its `min(g, rhs)` and
/// hence `secondary` are finite, and this key never collides with a live one.
const NOT_QUEUED: Key = Key::INFINITE;

/// Priority queue over vertex indices `0..capacity`.
#[derive(Debug, Clone)]
pub struct KeyedQueue {
    heap: BinaryHeap<Reverse<(Key, u32)>>,
    live_keys: Vec<Key>,
    live_count: usize,
}

impl KeyedQueue {
    /// An empty queue for vertices `0..capacity` (capacity ≤ `u32::MAX`).
    pub fn new(capacity: usize) -> Self {
        Self {
            heap: BinaryHeap::new(),
            live_keys: vec![NOT_QUEUED; capacity],
            live_count: 0,
        }
    }

    /// Number of vertices in the queue.
    pub fn len(&self) -> usize {
        self.live_count
    }

    /// Whether the queue holds no vertex.
    pub fn is_empty(&self) -> bool {
        self.live_count == 0
    }

    /// Whether `vertex` is in the queue.
    pub fn contains(&self, vertex: usize) -> bool {
        self.live_keys
            .get(vertex)
            .is_some_and(|&key| key != NOT_QUEUED)
    }

    /// The key of `vertex`, if queued.
    pub fn key_of(&self, vertex: usize) -> Option<Key> {
        self.live_keys
            .get(vertex)
            .copied()
            .filter(|&key| key != NOT_QUEUED)
    }

    /// Inserts `vertex` with `key`, or changes its key if already queued. Out-of-range
    /// vertices are ignored.
    pub fn insert_or_update(&mut self, vertex: usize, key: Key) {
        let Some(slot) = self.live_keys.get_mut(vertex) else {
            return;
        };
        if *slot == key {
            return;
        }
        if *slot == NOT_QUEUED {
            self.live_count += 1;
        }
        *slot = key;
        // `vertex < capacity ≤ u32::MAX`, checked by the caller's grid size bound.
        self.heap.push(Reverse((key, vertex as u32)));
        self.purge_if_bloated();
    }

    /// Removes `vertex` if queued.
    pub fn remove(&mut self, vertex: usize) {
        if let Some(slot) = self.live_keys.get_mut(vertex)
            && *slot != NOT_QUEUED
        {
            *slot = NOT_QUEUED;
            self.live_count -= 1;
        }
    }

    /// The vertex with the smallest key and that key, or `None` when empty.
    pub fn top(&mut self) -> Option<(usize, Key)> {
        while let Some(&Reverse((key, vertex))) = self.heap.peek() {
            let vertex = vertex as usize;
            if self.live_keys[vertex] == key {
                return Some((vertex, key));
            }
            self.heap.pop();
        }
        None
    }

    /// The smallest key, or [`Key::INFINITE`] when empty.
    pub fn top_key(&mut self) -> Key {
        self.top().map_or(Key::INFINITE, |(_, key)| key)
    }

    /// Removes every vertex.
    pub fn clear(&mut self) {
        self.heap.clear();
        self.live_keys.fill(NOT_QUEUED);
        self.live_count = 0;
    }

    fn purge_if_bloated(&mut self) {
        if self.heap.len() > 1024 && self.heap.len() > 4 * self.live_count {
            let live_keys = &self.live_keys;
            self.heap
                .retain(|&Reverse((key, vertex))| live_keys[vertex as usize] == key);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(primary: Cost, secondary: Cost) -> Key {
        Key { primary, secondary }
    }

    #[test]
    fn orders_lexicographically_and_tracks_membership() {
        let mut queue = KeyedQueue::new(4);
        queue.insert_or_update(0, key(5, 1));
        queue.insert_or_update(1, key(3, 9));
        queue.insert_or_update(2, key(3, 2));
        assert_eq!(queue.top(), Some((2, key(3, 2))));
        queue.insert_or_update(2, key(7, 0));
        assert_eq!(queue.top(), Some((1, key(3, 9))));
        queue.remove(1);
        assert!(!queue.contains(1));
        assert_eq!(queue.top(), Some((0, key(5, 1))));
        queue.remove(0);
        assert_eq!(queue.top(), Some((2, key(7, 0))));
        queue.remove(2);
        assert_eq!(queue.top_key(), Key::INFINITE);
        assert!(queue.is_empty());
    }

    #[test]
    fn reinsert_after_remove_with_same_key_is_live() {
        let mut queue = KeyedQueue::new(2);
        queue.insert_or_update(1, key(1, 1));
        queue.remove(1);
        queue.insert_or_update(1, key(1, 1));
        assert_eq!(queue.len(), 1);
        assert_eq!(queue.top(), Some((1, key(1, 1))));
        queue.remove(1);
        assert_eq!(queue.top(), None);
    }

    #[test]
    fn purges_stale_entries() {
        let mut queue = KeyedQueue::new(1);
        for primary in 0..10_000 {
            queue.insert_or_update(0, key(primary, 0));
        }
        assert!(queue.heap.len() <= 4 * 1024);
        assert_eq!(queue.top(), Some((0, key(9_999, 0))));
    }
}
