//! Prose fitted to the terminal: a line wider than the screen is broken at spaces, its
//! continuation indented two more than the line, so that a terminal never folds a word in
//! half. Only for people at a terminal: a pipe or a file keeps every line whole, for grep.

/// `text` with every line wider than `width` characters broken at spaces. A word longer
/// than the line (a path, a URI) stays whole on a line of its own.
pub(crate) fn wrap(text: &str, width: usize) -> String {
    let mut out = String::with_capacity(text.len() + 16);
    for (i, line) in text.split('\n').enumerate() {
        if i > 0 {
            out.push('\n');
        }
        wrap_line(line, width, &mut out);
    }
    out
}

fn wrap_line(line: &str, width: usize, out: &mut String) {
    if line.chars().count() <= width {
        out.push_str(line);
        return;
    }
    let body = line.trim_start_matches(' ');
    let indent = line.len() - body.len();
    let hanging = " ".repeat(indent + 2);
    out.push_str(&line[..indent]);
    let mut used = indent;
    let mut first_on_line = true;
    for word in body.split(' ').filter(|w| !w.is_empty()) {
        let len = word.chars().count();
        if !first_on_line && used + 1 + len > width {
            out.push('\n');
            out.push_str(&hanging);
            used = hanging.len();
            first_on_line = true;
        }
        if !first_on_line {
            out.push(' ');
            used += 1;
        }
        out.push_str(word);
        used += len;
        first_on_line = false;
    }
}

#[cfg(test)]
mod tests {
    use super::wrap;

    #[test]
    fn a_line_that_fits_is_left_as_it_is() {
        assert_eq!(wrap("node 5:  two  spaces kept", 80), "node 5:  two  spaces kept");
        assert_eq!(wrap("a\n\nb", 1), "a\n\nb");
    }

    #[test]
    fn a_long_line_breaks_at_spaces_with_a_hanging_indent() {
        let text = "warning: node 10 sends 0x1008:0 without end: cut at 255 bytes";
        assert_eq!(wrap(text, 30), "warning: node 10 sends\n  0x1008:0 without end: cut at\n  255 bytes");
        for line in wrap(text, 30).lines() {
            assert!(line.chars().count() <= 30, "{line:?}");
        }
    }

    #[test]
    fn an_indented_line_keeps_its_indent_and_continues_under_it() {
        assert_eq!(
            wrap("  fix: power the device and check its wiring", 20),
            "  fix: power the\n    device and check\n    its wiring"
        );
    }

    #[test]
    fn a_word_wider_than_the_line_stays_whole() {
        assert_eq!(
            wrap("see /a/very/long/path/to/a/file.dcf now", 10),
            "see\n  /a/very/long/path/to/a/file.dcf\n  now"
        );
    }

    #[test]
    fn characters_not_bytes_are_counted() {
        assert_eq!(wrap("näöü äöü", 8), "näöü äöü");
    }
}
