//! Turns to render, shared fairly between clients: at most `concurrent_renders` renders run at
//! once, and when a turn comes free it goes to the clients waiting in turn (round robin), each
//! client's own requests first come, first served. One client's backlog (fifty render jobs of
//! full-HD frames) then delays another client's small frame by one render at most, where a
//! single first-come queue made it wait for the whole backlog.
//!
//! A render that shows an edit to someone watching (a stream's first pass after its scene or its
//! image changed, [`Urgency::Edit`]) goes before the others: a camera dragged in a viewer is seen
//! one pass later, not one round of every client's renders later. Edits have a ring of their
//! own, and while other renders wait too, the turns handed on alternate between the two rings,
//! so edits take at most every other turn: a client editing without pause delays everyone
//! else's renders by one render each at most, as one more client would.
//!
//! A client is a connection ([`Client`]): the server has one token for everyone, so nothing
//! finer tells its clients apart. A client that opens many connections at once gets a share for
//! each; render jobs, the way to queue many frames, are all their creating connection's.

use std::collections::{BTreeMap, VecDeque};
use std::ops::Bound::{Excluded, Unbounded};
use std::sync::{Arc, Mutex};

use tokio::sync::oneshot;

/// Who asked for a render: the connection its request came on, numbered in the order the
/// server accepted them. Requests that came some other way (the router driven directly, as
/// tests do) are [`Client::ANY`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Client(pub u64);

impl Client {
    /// A request without a connection of its own.
    pub const ANY: Client = Client(0);
}

/// How soon a render should have its turn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Urgency {
    /// Its turn in the round of the clients: frames, render jobs, a stream's refining passes.
    InTurn,
    /// It shows an edit to someone waiting to see it: ahead of the round, alternating with it.
    Edit,
}

/// The turns and who waits for them.
pub(crate) struct Turns(Arc<Mutex<Queue>>);

#[derive(Default)]
struct Queue {
    /// Turns nobody holds.
    free: usize,
    /// Renders showing edits.
    edits: Ring,
    /// Every other render.
    in_turn: Ring,
    /// Whether the last turn handed on went to an edit.
    edit_last: bool,
}

/// Clients waiting, served round robin.
#[derive(Default)]
struct Ring {
    /// Each waiting client's waiters, oldest first.
    waiting: BTreeMap<Client, VecDeque<oneshot::Sender<Turn>>>,
    /// The client served last: the next turn goes to the first waiting client after it.
    last: Option<Client>,
}

impl Ring {
    /// The oldest waiter of the first waiting client after the one served last, round the ring.
    fn next(&mut self) -> Option<oneshot::Sender<Turn>> {
        let after = self.last.and_then(|last| self.waiting.range((Excluded(last), Unbounded)).next());
        let client = *after.or_else(|| self.waiting.iter().next())?.0;
        let waiters = self.waiting.get_mut(&client).expect("a listed client waits");
        let sender = waiters.pop_front().expect("a listed client has a waiter");
        if waiters.is_empty() {
            self.waiting.remove(&client);
        }
        self.last = Some(client);
        Some(sender)
    }
}

/// A turn to render: dropping it hands it to the next waiter, or frees it.
pub(crate) struct Turn(Option<Arc<Mutex<Queue>>>);

impl Turns {
    /// `count` turns (at least one).
    pub fn new(count: usize) -> Turns {
        Turns(Arc::new(Mutex::new(Queue { free: count.max(1), ..Queue::default() })))
    }

    /// Waits for a turn for `client`. Dropping the future before it is ready leaves the queue as
    /// if it had never waited (a turn handed to it meanwhile goes on to the next waiter).
    pub async fn take(&self, client: Client, urgency: Urgency) -> Turn {
        let receiver = {
            let mut queue = lock(&self.0);
            let queue = &mut *queue;
            // A free turn means nobody waits: turns are handed on while anyone does.
            let free = queue.free > 0;
            let ring = match urgency {
                Urgency::Edit => &mut queue.edits,
                Urgency::InTurn => &mut queue.in_turn,
            };
            if free {
                queue.free -= 1;
                // Served now, as a turn handed on would be: others waiting next go first.
                ring.last = Some(client);
                queue.edit_last = urgency == Urgency::Edit;
                return Turn(Some(self.0.clone()));
            }
            let (sender, receiver) = oneshot::channel();
            ring.waiting.entry(client).or_default().push_back(sender);
            receiver
        };
        // A turn sent to a receiver dropped before it read it is dropped with it, and so goes
        // on to the next waiter.
        receiver.await.expect("a waiter's sender is dropped only by sending it a turn")
    }
}

impl Drop for Turn {
    fn drop(&mut self) {
        let Some(queue) = self.0.take() else { return };
        let mut next = lock(&queue);
        loop {
            // An edit, unless the last turn went to one and other renders wait too.
            let edit = !next.edits.waiting.is_empty() && !(next.edit_last && !next.in_turn.waiting.is_empty());
            let sender = if edit { next.edits.next() } else { next.in_turn.next() };
            let Some(sender) = sender else {
                next.free += 1;
                return;
            };
            next.edit_last = edit;
            // Sent, it is the waiter's turn (dropped unread, it comes back here); a waiter
            // that has gone gives it straight back.
            match sender.send(Turn(Some(queue.clone()))) {
                Ok(()) => return,
                Err(mut turn) => turn.0 = None,
            }
        }
    }
}

fn lock(queue: &Mutex<Queue>) -> std::sync::MutexGuard<'_, Queue> {
    queue.lock().unwrap_or_else(|e| e.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Who gets each turn, as `order` records it, when one turn goes round `waiters` (clients
    /// waiting in turn, or for an edit: `(client, urgency)`), queued in this order.
    async fn served_as(waiters: &[(u64, Urgency)]) -> Vec<u64> {
        let turns = Turns::new(1);
        let held = turns.take(Client(99), Urgency::InTurn).await;
        let order = Arc::new(Mutex::new(Vec::new()));
        let mut tasks = Vec::new();
        for &(client, urgency) in waiters {
            let (turns, order) = (Turns(turns.0.clone()), order.clone());
            tasks.push(tokio::spawn(async move {
                let turn = turns.take(Client(client), urgency).await;
                order.lock().unwrap().push(client);
                drop(turn);
            }));
            // Queued in this order.
            tokio::task::yield_now().await;
        }
        drop(held);
        for task in tasks {
            task.await.unwrap();
        }
        Arc::try_unwrap(order).unwrap().into_inner().unwrap()
    }

    /// [`served_as`] with every client waiting in turn.
    async fn served(waiters: &[u64]) -> Vec<u64> {
        served_as(&waiters.iter().map(|&c| (c, Urgency::InTurn)).collect::<Vec<_>>()).await
    }

    /// One client's five requests and another's one: the other's goes second, not sixth.
    #[tokio::test]
    async fn turns_go_round_the_clients() {
        assert_eq!(served(&[1, 1, 1, 1, 1, 2]).await, [1, 2, 1, 1, 1, 1]);
        assert_eq!(served(&[3, 3, 2, 2, 1]).await, [1, 2, 3, 2, 3]);
        // The ring closes after the highest client number there can be.
        assert_eq!(served(&[u64::MAX, u64::MAX, 1]).await, [u64::MAX, 1, u64::MAX]);
    }

    /// An edit goes before renders queued earlier, but edits take every other turn at most
    /// while other renders wait: edits of clients 3 and 4 alternate with the round of 1 and 2.
    #[tokio::test]
    async fn edits_go_first_and_alternate_with_the_round() {
        use Urgency::{Edit, InTurn};
        let waiters = [(1, InTurn), (1, InTurn), (2, InTurn), (3, Edit), (3, Edit), (4, Edit), (3, Edit)];
        assert_eq!(served_as(&waiters).await, [3, 1, 4, 2, 3, 1, 3]);
        // With nothing else waiting, edits follow one another.
        assert_eq!(served_as(&[(5, Edit), (6, Edit), (5, Edit)]).await, [5, 6, 5]);
    }

    /// A waiter that goes away neither holds a turn nor loses one: the next gets it.
    #[tokio::test]
    async fn a_waiter_that_goes_away_passes_its_turn_on() {
        let turns = Turns::new(1);
        let held = turns.take(Client(1), Urgency::InTurn).await;
        let gone = tokio::spawn({
            let turns = Turns(turns.0.clone());
            async move { drop(turns.take(Client(2), Urgency::Edit).await) }
        });
        tokio::task::yield_now().await;
        gone.abort();
        let _ = gone.await;
        drop(held);
        let again = tokio::time::timeout(std::time::Duration::from_secs(1), turns.take(Client(3), Urgency::InTurn)).await;
        assert!(again.is_ok(), "the turn was lost with the waiter that went away");
        assert_eq!(lock(&turns.0).free, 0);
        drop(again);
        assert_eq!(lock(&turns.0).free, 1);
    }
}
