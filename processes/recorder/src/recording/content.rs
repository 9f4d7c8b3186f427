//! What a recording holds besides hopnav's own non-image channels (`[recorder]` keys).

use super::foxglove_channels::FoxgloveTopic;

/// The optional parts of a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RecordingContent {
    /// Foxglove's messages beside hopnav's own (`[recorder] foxglove`).
    pub foxglove: bool,
    /// Camera images, in hopnav's channels and as Foxglove RawImages (`[recorder] images`).
    pub images: bool,
}

impl RecordingContent {
    /// Everything: Foxglove channels and images (the default).
    pub const EVERYTHING: Self = Self {
        foxglove: true,
        images: true,
    };

    /// The Foxglove channels to create, in [`FoxgloveTopic::ALL`]'s order.
    pub fn foxglove_topics(self) -> impl Iterator<Item = FoxgloveTopic> {
        FoxgloveTopic::ALL
            .into_iter()
            .filter(move |topic| self.foxglove && (self.images || !topic.is_image()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_images_no_image_channel_is_created() {
        let without_images = RecordingContent {
            foxglove: true,
            images: false,
        };
        let topics: Vec<_> = without_images.foxglove_topics().collect();
        assert_eq!(topics.len(), FoxgloveTopic::ALL.len() - 3);
        assert!(topics.iter().all(|topic| !topic.is_image()));
        assert_eq!(RecordingContent::EVERYTHING.foxglove_topics().count(), 8);
        let none = RecordingContent {
            foxglove: false,
            images: true,
        };
        assert_eq!(none.foxglove_topics().count(), 0);
    }
}
