//! The backends: each offers the [`crate::bus::Bus`] services over one kind of link, either as
//! a [`crate::bus::FrameLink`] of raw frames (served by [`crate::bus::Master`]) or as a `Bus`
//! of its own (the EPOS2 gateway). canctl's `connect::open` is the one place that picks one;
//! the simulator's link is canctl's `sim::SimLink`.

#[cfg(target_os = "linux")]
mod can_netlink;
pub mod epos2;
pub mod slcan;
#[cfg(target_os = "linux")]
pub mod socketcan;
pub mod socketcand;

/// CAN interfaces present (ARPHRD_CAN = 280 in /sys/class/net/*/type).
pub fn can_interfaces() -> Vec<String> {
    let mut out: Vec<String> = std::fs::read_dir("/sys/class/net")
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| std::fs::read_to_string(e.path().join("type")).is_ok_and(|t| t.trim() == "280"))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    out.sort();
    out
}

/// Serial ports present.
pub fn serial_ports() -> Vec<String> {
    let mut out: Vec<String> =
        serialport::available_ports().unwrap_or_default().into_iter().map(|p| p.port_name).collect();
    out.sort();
    out
}
