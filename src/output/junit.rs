//! JUnit XML, the test report CI systems read: what `--format junit` writes.

use std::fmt::Write;

/// Test results for CI systems: one suite of cases.
pub struct TestSuite {
    /// The suite's name: the command.
    pub name: String,
    /// One case per check.
    pub cases: Vec<TestCase>,
}

/// One check's result in a [`TestSuite`].
pub struct TestCase {
    /// What is tested (`node 5 (C01)`), shown as the class.
    pub class: String,
    /// The check (`identity`).
    pub name: String,
    /// What was found, in a sentence.
    pub detail: String,
    /// Why the case failed: a one-line message; `None` when it passed.
    pub failure: Option<String>,
}

/// Text for an XML attribute or element: markup escaped, and the characters XML 1.0 cannot
/// carry at all (control characters but tab, LF, CR) shown as `\xNN`.
fn xml_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => {
                let _ = write!(out, "\\x{:02X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}

/// JUnit XML as Jenkins, GitLab and GitHub test reporters read it.
pub(crate) fn junit_xml(suite: &TestSuite) -> String {
    junit_xml_suites(&suite.name, std::slice::from_ref(suite))
}

/// [`junit_xml`] of several suites (a command run on several buses: one suite per bus),
/// `name` the whole run's.
pub(crate) fn junit_xml_suites(name: &str, suites: &[TestSuite]) -> String {
    let failed = |s: &TestSuite| s.cases.iter().filter(|c| c.failure.is_some()).count();
    let failures: usize = suites.iter().map(failed).sum();
    let tests: usize = suites.iter().map(|s| s.cases.len()).sum();
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let name = xml_text(name);
    let _ = writeln!(x, "<testsuites name=\"{name}\" tests=\"{tests}\" failures=\"{failures}\" errors=\"0\">");
    for suite in suites {
        junit_suite_xml(&mut x, suite, failed(suite));
    }
    x.push_str("</testsuites>\n");
    x
}

fn junit_suite_xml(x: &mut String, suite: &TestSuite, failures: usize) {
    let (name, tests) = (xml_text(&suite.name), suite.cases.len());
    let _ = writeln!(
        x,
        "  <testsuite name=\"{name}\" tests=\"{tests}\" failures=\"{failures}\" errors=\"0\" skipped=\"0\">"
    );
    for c in &suite.cases {
        let _ = write!(x, "    <testcase classname=\"{}\" name=\"{}\"", xml_text(&c.class), xml_text(&c.name));
        match &c.failure {
            None => {
                let _ = writeln!(x, ">\n      <system-out>{}</system-out>\n    </testcase>", xml_text(&c.detail));
            }
            Some(message) => {
                let _ = writeln!(
                    x,
                    ">\n      <failure message=\"{}\" type=\"difference\">{}</failure>\n    </testcase>",
                    xml_text(message),
                    xml_text(&c.detail)
                );
            }
        }
    }
    x.push_str("  </testsuite>\n");
}
