//! canctl's integration tests, one binary (cargo's own testsuite layout): a module per
//! area, each running the built `canctl` or the library the way its users do. One binary
//! links once and runs every test in one pool, where 58 binaries each linked the whole crate
//! and ran one after the other.
//!
//! The kernel tests (SocketCAN, slcand, python peers on vcan0) are the modules that
//! `scripts/kernel-tests.sh` names: they say "skipped" without vcan0 and run in its VM.
//! Two tests stand beside this binary: `tests/dst/`, the seeded simulation, which CI runs
//! in a release build that this whole suite need not pay for; and `tests/library.rs`, the
//! crate as a library user builds it, without the command line (`--no-default-features`).
//! The interruption tests run a second binary, `tests/seams/canctl.rs`: canctl's own `main`
//! with a test seam that the shipped canctl lacks (`common::interrupted`).

mod common;

mod bus_decorators;
mod buses;
mod completion;
mod completion_forms;
mod config_check;
mod config_eds;
mod config_store;
mod data_types_python;
mod data_types_sdo;
mod dcf_roundtrip;
mod diagnostics;
mod doctor;
mod doctor_link;
mod doctor_vcan;
mod drive;
mod eds_corpus;
mod epos2_faults;
mod epos2_pty;
mod epos2_wire;
mod errors;
mod exit_codes;
mod firmware;
mod firmware_cli;
mod firmware_jobs;
mod firmware_vcan;
mod friction;
mod generated_docs;
mod health;
mod health_stall;
mod interop_canopen;
mod interop_durand;
mod interop_program;
mod interop_socketcand;
mod interrupt_commands;
mod interrupt_launch;
mod interruption;
mod layers;
mod lss_lost_frames;
mod lss_pace;
mod many_buses;
mod network;
mod network_set_baud;
mod network_vcan;
mod node_id_clash;
mod output_safety;
mod project_file;
mod readme_examples;
mod readme_tour;
mod sdo_faults;
mod sim_eds;
mod sim_profiles;
mod sim_scan_sdo_nmt;
mod slcan_kernel;
mod slcan_pty;
mod socketcan_vcan;
mod stream_monitor;
mod version;
mod xdd;
