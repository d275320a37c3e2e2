pub mod golden_messages;
pub mod random;
