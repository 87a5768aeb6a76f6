//! The exit codes are documented in three places that must agree: the README's table,
//! `canctl --help`, and `ErrorClass::exit_code` (the only place the code chooses them).

use crate::common;

use canctl::error::ErrorClass;
use std::collections::BTreeSet;

/// 0 ends a command that succeeded; it is no error's code.
const SUCCESS: i32 = 0;

fn readme_codes() -> BTreeSet<i32> {
    let readme = include_str!("../../README.md");
    let section = readme.split("\n## Exit codes\n").nth(1).expect("README has an \"## Exit codes\" section");
    let section = section.split("\n## ").next().unwrap();
    section.lines().filter_map(|l| l.strip_prefix('|')?.split('|').next()?.trim().parse().ok()).collect()
}

fn help_codes() -> BTreeSet<i32> {
    let r = common::bare(&["--help"]);
    let section = r.stdout.split("Exit codes:\n").nth(1).expect("--help lists the exit codes");
    section.lines().map_while(|l| l.split_whitespace().next()?.parse().ok()).collect()
}

fn class_codes() -> BTreeSet<i32> {
    ErrorClass::ALL.iter().map(|c| c.exit_code()).collect()
}

#[test]
fn every_error_class_has_its_code_in_the_readme_and_every_documented_code_is_used() {
    let readme = readme_codes();
    let mut produced = class_codes();
    produced.insert(SUCCESS);
    assert_eq!(readme, produced, "README's exit codes vs ErrorClass::exit_code (and 0 for success)");
}

#[test]
fn help_lists_the_same_exit_codes_as_the_readme() {
    assert_eq!(help_codes(), readme_codes());
}

#[test]
fn no_two_error_classes_share_a_code() {
    assert_eq!(class_codes().len(), ErrorClass::ALL.len());
}
