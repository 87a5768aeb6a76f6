#![no_main]
use canctl::canopen::sdo::SdoClient;
use canctl::canopen::ObjAddr;

// Answers from a device: every client state machine, fed any sequence of payloads.
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let addr = ObjAddr::new(0x2000, 1);
    for mut client in [
        SdoClient::upload(addr, false),
        SdoClient::upload(addr, true),
        SdoClient::download(addr, vec![7; 100], true),
        SdoClient::download(addr, vec![7; 10], false),
    ] {
        client.start();
        for chunk in data.chunks(8) {
            if client.on_response(chunk).is_err() {
                break;
            }
        }
    }
});
