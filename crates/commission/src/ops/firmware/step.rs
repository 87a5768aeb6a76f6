//! The steps of a firmware download and how one node's download ended, as a progress
//! display is told them.

use serde::Serialize;

/// One step of the sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Step {
    /// 0x1F56 read: the identification of the program the device has.
    ReadId,
    /// NMT pre-operational sent.
    PreOperational,
    /// 0x1F51 = 0 answered.
    Stop,
    /// The device rebooted into its bootloader (its boot-up came).
    BootedBootloader,
    /// 0x1F51 = 3 answered.
    Clear,
    /// 0x1F57 no longer busy after the clear.
    Erased,
    /// 0x1F50 written whole.
    Download,
    /// 0x1F57 no longer busy after the download, and no error.
    Written,
    /// 0x1F56 equals the image's identification.
    IdChecked,
    /// 0x1F51 = 1 sent (answered, or the device reset before answering).
    Start,
    /// The boot-up of the new program came.
    BootUp,
    /// Through a link that shows no boot-up (a gateway): the device answers again.
    Answers,
    /// A heartbeat of the running program came.
    Heartbeat,
    /// 0x1F51 = 0x80 answered: the new program is kept.
    Confirm,
}

impl Step {
    /// The step in words.
    pub fn describe(self) -> &'static str {
        match self {
            Step::ReadId => "read the software identification (0x1F56)",
            Step::PreOperational => "NMT pre-operational",
            Step::Stop => "stop the program (0x1F51 = 0)",
            Step::BootedBootloader => "rebooted into its bootloader (boot-up)",
            Step::Clear => "clear the flash (0x1F51 = 3)",
            Step::Erased => "erase done (0x1F57 not busy)",
            Step::Download => "program data written (0x1F50)",
            Step::Written => "flash written (0x1F57 not busy, no error)",
            Step::IdChecked => "identification checked (0x1F56)",
            Step::Start => "start the program (0x1F51 = 1)",
            Step::BootUp => "boot-up of the new program",
            Step::Answers => "the device answers again (no boot-up seen through this link)",
            Step::Heartbeat => "heartbeat",
            Step::Confirm => "confirmed (0x1F51 = 0x80)",
        }
    }
}

/// How one node's download ended, for a progress display to word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DownloadEnd {
    /// Skipped: the node runs the image already.
    Skipped,
    /// Downloaded.
    Done,
    /// Stopped by the user.
    Interrupted,
    /// Failed.
    Failed,
}
