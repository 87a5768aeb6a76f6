
use builtin;
use str;

set edit:completion:arg-completer[canctl] = {|@words|
    fn spaces {|n|
        builtin:repeat $n ' ' | str:join ''
    }
    fn cand {|text desc|
        edit:complex-candidate $text &display=$text' '(spaces (- 14 (wcswidth $text)))$desc
    }
    var command = 'canctl'
    for word $words[1..-1] {
        if (str:has-prefix $word '-') {
            break
        }
        set command = $command';'$word
    }
    var completions = [
        &'canctl'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand scan 'Find every node on the bus'
            cand sdo 'Read and write objects (SDO)'
            cand nmt 'Start, stop and reset nodes, or ask their NMT state'
            cand sim 'Run the simulated network on a CAN interface or behind a serial link, or manage its state'
            cand completions 'Print a shell completion script'
            cand man 'Print the man page, or write every page to a directory'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;scan'= {
            cand --window 'How long to wait for answers to the probes'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;sdo'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand read 'Read an object (SDO upload)'
            cand write 'Write an object (SDO download)'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;sdo;read'= {
            cand -t 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d'
            cand --type 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d'
            cand --out 'Write the raw bytes to this file instead of printing them'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand --no-block 'Never use block transfer (segmented instead)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;sdo;write'= {
            cand -t 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d'
            cand --type 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand --verify 'Read the object back and compare (exit 6 when it differs)'
            cand --no-block 'Never use block transfer (segmented instead)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;sdo;help'= {
            cand read 'Read an object (SDO upload)'
            cand write 'Write an object (SDO download)'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;sdo;help;read'= {
        }
        &'canctl;sdo;help;write'= {
        }
        &'canctl;sdo;help;help'= {
        }
        &'canctl;nmt'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand start 'Put a node (or all) in Operational'
            cand stop 'Put a node (or all) in Stopped'
            cand preop 'Put a node (or all) in Pre-operational'
            cand reset 'Reset a node''s application (or all nodes'') and wait for the boot-up'
            cand reset-comm 'Reset a node''s communication (or all nodes'') and wait for the boot-up'
            cand state 'Report a node''s NMT state, from its heartbeat or by node guarding'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;nmt;start'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;nmt;stop'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;nmt;preop'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;nmt;reset'= {
            cand --wait 'How long to wait for boot-up messages'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;nmt;reset-comm'= {
            cand --wait 'How long to wait for boot-up messages'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;nmt;state'= {
            cand --listen 'How long to listen for a heartbeat before asking by node guarding'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;nmt;help'= {
            cand start 'Put a node (or all) in Operational'
            cand stop 'Put a node (or all) in Stopped'
            cand preop 'Put a node (or all) in Pre-operational'
            cand reset 'Reset a node''s application (or all nodes'') and wait for the boot-up'
            cand reset-comm 'Reset a node''s communication (or all nodes'') and wait for the boot-up'
            cand state 'Report a node''s NMT state, from its heartbeat or by node guarding'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;nmt;help;start'= {
        }
        &'canctl;nmt;help;stop'= {
        }
        &'canctl;nmt;help;preop'= {
        }
        &'canctl;nmt;help;reset'= {
        }
        &'canctl;nmt;help;reset-comm'= {
        }
        &'canctl;nmt;help;state'= {
        }
        &'canctl;nmt;help;help'= {
        }
        &'canctl;sim'= {
            cand --socketcan 'Put the devices on this CAN interface (vcan0, can0) and answer there'
            cand --baud 'Pace bytes as a serial line at this bit rate would (10 bits a byte)'
            cand --fault 'Inject a fault: nack, crc, garbage, drop or mute, on frame N (KIND@N) or every frame (KIND@*)'
            cand --can-timeout 'How long the EPOS2 waits for an SDO answer on the CAN bus'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand --epos2-rs232 'Serve an EPOS2 speaking the RS232 protocol (with the ''O''/''F'' handshake)'
            cand --epos2-usb 'Serve an EPOS2 speaking the USB protocol (DLE/STX framing)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand reset 'Forget the simulated network''s saved state: devices start as built'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;sim;reset'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;sim;help'= {
            cand reset 'Forget the simulated network''s saved state: devices start as built'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;sim;help;reset'= {
        }
        &'canctl;sim;help;help'= {
        }
        &'canctl;completions'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;man'= {
            cand --out 'Write canctl.1 and one page per subcommand into this directory'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds)'
            cand --format 'Output format'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;help'= {
            cand scan 'Find every node on the bus'
            cand sdo 'Read and write objects (SDO)'
            cand nmt 'Start, stop and reset nodes, or ask their NMT state'
            cand sim 'Run the simulated network on a CAN interface or behind a serial link, or manage its state'
            cand completions 'Print a shell completion script'
            cand man 'Print the man page, or write every page to a directory'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;help;scan'= {
        }
        &'canctl;help;sdo'= {
            cand read 'Read an object (SDO upload)'
            cand write 'Write an object (SDO download)'
        }
        &'canctl;help;sdo;read'= {
        }
        &'canctl;help;sdo;write'= {
        }
        &'canctl;help;nmt'= {
            cand start 'Put a node (or all) in Operational'
            cand stop 'Put a node (or all) in Stopped'
            cand preop 'Put a node (or all) in Pre-operational'
            cand reset 'Reset a node''s application (or all nodes'') and wait for the boot-up'
            cand reset-comm 'Reset a node''s communication (or all nodes'') and wait for the boot-up'
            cand state 'Report a node''s NMT state, from its heartbeat or by node guarding'
        }
        &'canctl;help;nmt;start'= {
        }
        &'canctl;help;nmt;stop'= {
        }
        &'canctl;help;nmt;preop'= {
        }
        &'canctl;help;nmt;reset'= {
        }
        &'canctl;help;nmt;reset-comm'= {
        }
        &'canctl;help;nmt;state'= {
        }
        &'canctl;help;sim'= {
            cand reset 'Forget the simulated network''s saved state: devices start as built'
        }
        &'canctl;help;sim;reset'= {
        }
        &'canctl;help;completions'= {
        }
        &'canctl;help;man'= {
        }
        &'canctl;help;help'= {
        }
    ]
    $completions[$command]
}
