//! One small error enum per fallible transport operation.

/// Opening a topic port failed.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// The topic name is not a valid iceoryx2 service name.
    #[error("topic name {0:?} is not a valid service name")]
    BadTopicName(String),
    /// The publish-subscribe service could not be opened or created (e.g. it exists with an
    /// incompatible type or quality of service).
    #[error("topic {topic:?}: cannot open data service: {reason}")]
    DataService {
        /// Topic name.
        topic: String,
        /// iceoryx2's reason.
        reason: String,
    },
    /// The event service could not be opened or created.
    #[error("topic {topic:?}: cannot open event service: {reason}")]
    EventService {
        /// Topic name.
        topic: String,
        /// iceoryx2's reason.
        reason: String,
    },
    /// The topic does not exist (a tool opens only topics of a running launch).
    #[error("topic {0:?} does not exist in this launch")]
    NoSuchTopic(String),
    /// The topic has no subscriber slot to spare for a tool: a tool takes one only if one more
    /// stays free for a restarting consumer of the graph.
    #[error(
        "topic {topic:?} has no subscriber slot to spare ({in_use} of {max_subscribers} in use; a tool leaves one free for a restarting consumer): stop another tool on it, or try again"
    )]
    NoFreeSubscriberSlot {
        /// Topic name.
        topic: String,
        /// Subscribers the topic has now.
        in_use: usize,
        /// The topic's subscriber limit.
        max_subscribers: usize,
    },
    /// The port could not be created (e.g. too many publishers, or shared memory exhausted).
    #[error("topic {topic:?}: cannot create port: {reason}")]
    Port {
        /// Topic name.
        topic: String,
        /// iceoryx2's reason.
        reason: String,
    },
}

/// Sending a sample failed.
#[derive(Debug, thiserror::Error)]
pub enum SendError {
    /// No sample could be loaned: shared memory is full or every sample is still borrowed.
    #[error("topic {topic:?}: no shared memory to loan a sample: {reason}")]
    Loan {
        /// Topic name.
        topic: String,
        /// iceoryx2's reason.
        reason: String,
    },
    /// The requested slice is longer than the port was sized for.
    #[error("topic {topic:?}: slice of {requested} elements exceeds the maximum of {max}")]
    SliceTooLong {
        /// Topic name.
        topic: String,
        /// Requested length.
        requested: usize,
        /// Port maximum.
        max: usize,
    },
    /// Delivery failed.
    #[error("topic {topic:?}: send failed: {reason}")]
    Deliver {
        /// Topic name.
        topic: String,
        /// iceoryx2's reason.
        reason: String,
    },
    /// The producer's fill function refused to produce the sample.
    #[error("topic {topic:?}: producer could not fill the sample: {reason}")]
    Fill {
        /// Topic name.
        topic: String,
        /// The producer's reason.
        reason: String,
    },
}

/// Receiving failed for a reason other than an invalid sample (those are counted, not errors).
#[derive(Debug, thiserror::Error)]
pub enum ReceiveError {
    /// iceoryx2 could not hand out a sample (connection broken, too many borrowed samples).
    #[error("topic {topic:?}: receive failed: {reason}")]
    Transport {
        /// Topic name.
        topic: String,
        /// iceoryx2's reason.
        reason: String,
    },
}
