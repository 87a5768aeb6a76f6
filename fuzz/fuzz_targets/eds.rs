#![no_main]
// EDS/DCF files come from vendors and users: any bytes must give a dictionary or an error.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(eds) = canctl::od::eds::parse(data, "fuzz.eds") {
        // What was read must write and read back, or be refused with a reason (a control
        // character in a string, say, which a lenient reader lets through).
        if let Ok(bytes) = canctl::od::eds::write_bytes(&eds.dict, None, &Default::default()) {
            canctl::od::eds::parse(&bytes, "again.eds").expect("written EDS reads back");
        }
    }
});
