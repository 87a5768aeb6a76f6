//! The CiA 301 types beyond the common ones, written and read by type over SDO on the sim
//! network (node 10's DOMAIN 0x5FF0:14 holds any bytes): the wire bytes are CiA 301's.

use crate::common;
use common::Sim;

#[test]
fn wide_integers_times_and_unicode_go_over_sdo_by_type() {
    let sim = Sim::new();
    let cases = [
        ("i24", "-2", "FEFFFF"),
        ("u40", "4328719365", "0504030201"),
        ("i56", "-56", "C8FFFFFFFFFFFF"),
        // Day 14610 of the 1984 epoch (0x3912), noon: 43 200 000 ms.
        ("t", "2024-01-01T12:00:00.000", "002E93021239"),
        ("td", "1d 00:00:00.500", "F40100000100"),
        ("us", "abc✓", "6100620063001327"),
    ];
    for (t, text, wire) in cases {
        let w = sim.run(&["sdo", "write", "10", "5FF0:14", text, "--type", t]);
        assert_eq!(w.code, 0, "{t}: {}", w.stderr);
        let raw = sim.run(&["sdo", "read", "10", "5FF0:14", "--type", "d"]);
        assert_eq!(raw.stdout.trim(), wire, "{t} {text}: the bytes on the wire");
        let back = sim.run(&["sdo", "read", "10", "5FF0:14", "--type", t]);
        assert_eq!(back.stdout.trim(), text, "{t}");
    }
}
