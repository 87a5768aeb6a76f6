
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand lss 'Node-ids and bit rates over LSS (CiA 305): find, set, store, assign'
            cand store 'Save parameters to non-volatile memory (writes ''save'' to 0x1010)'
            cand restore 'Bring back default parameters (writes ''load'' to 0x1011)'
            cand stream-pdo 'Stream a node''s transmit PDOs, decoded'
            cand monitor 'Watch the bus: every frame decoded, as it happens'
            cand config 'Configuration files: dump a node to a DCF, compare, apply'
            cand sim 'Run the simulated network on a CAN interface or behind a serial link, or manage its state'
            cand settings 'Show the settings in force and where each comes from (flags, CANCTL_BUS, canctl.toml)'
            cand completions 'Print a shell completion script'
            cand man 'Print the man page, or write every page to a directory'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;scan'= {
            cand --window 'How long to wait for answers to the probes'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand -t 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary''s)'
            cand --type 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary''s)'
            cand --out 'Write the raw bytes to this file instead of printing them'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand -t 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary''s)'
            cand --type 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary''s)'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
        &'canctl;lss'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand inquire 'Read a device''s identity and node-id'
            cand set-id 'Give a device a node-id (1..127; 255 takes it away)'
            cand set-baud 'Configure a device''s bit rate (takes effect at `lss activate`, or stored and reset)'
            cand activate 'Switch configured bit rates on (every device in configuration state at once)'
            cand store 'Make a device keep its LSS node-id and bit rate across power cycles'
            cand fastscan 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)'
            cand assign 'Give every device without a node-id the next free one, and store it'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;lss;inquire'= {
            cand --identity 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)'
            cand --node '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --global 'Every LSS device on the bus at once (a broadcast)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;lss;set-id'= {
            cand --identity 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)'
            cand --node '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --global 'Every LSS device on the bus at once (a broadcast)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;lss;set-baud'= {
            cand --identity 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)'
            cand --node '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --global 'Every LSS device on the bus at once (a broadcast)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;lss;activate'= {
            cand --delay 'Switch delay in ms: the devices wait this long, switch, and wait as long again'
            cand --identity 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)'
            cand --node '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --global 'Every LSS device on the bus at once (a broadcast)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;lss;store'= {
            cand --identity 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)'
            cand --node '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --global 'Every LSS device on the bus at once (a broadcast)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;lss;fastscan'= {
            cand --step 'How long each fastscan step waits for an answer'
            cand --node 'Refused: an EPOS2 reached directly (node 0) has no LSS'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;lss;assign'= {
            cand --start 'The first node-id to give'
            cand --step 'How long each fastscan step waits for an answer'
            cand --node 'Refused: an EPOS2 reached directly (node 0) has no LSS'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --no-store 'Do not store the node-ids (they are lost at power-off)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;lss;help'= {
            cand inquire 'Read a device''s identity and node-id'
            cand set-id 'Give a device a node-id (1..127; 255 takes it away)'
            cand set-baud 'Configure a device''s bit rate (takes effect at `lss activate`, or stored and reset)'
            cand activate 'Switch configured bit rates on (every device in configuration state at once)'
            cand store 'Make a device keep its LSS node-id and bit rate across power cycles'
            cand fastscan 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)'
            cand assign 'Give every device without a node-id the next free one, and store it'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;lss;help;inquire'= {
        }
        &'canctl;lss;help;set-id'= {
        }
        &'canctl;lss;help;set-baud'= {
        }
        &'canctl;lss;help;activate'= {
        }
        &'canctl;lss;help;store'= {
        }
        &'canctl;lss;help;fastscan'= {
        }
        &'canctl;lss;help;assign'= {
        }
        &'canctl;lss;help;help'= {
        }
        &'canctl;store'= {
            cand --store-timeout 'How long the device may take to store (flash writes take a while)'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;restore'= {
            cand --store-timeout 'How long the device may take to restore'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --reset 'Reset the node afterwards and wait for it to boot with the defaults'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;stream-pdo'= {
            cand --tpdo 'Which TPDOs (default: every valid one of 1..4)'
            cand --count 'Stop after this many records'
            cand --duration 'Stop after this long'
            cand --sync 'Send SYNC at this period (for synchronous PDOs, transmission types 0..240)'
            cand --map 'Map these objects into the (first) TPDO for this session: 6064:0,606C:0'
            cand --event 'With --map: event timer in ms'
            cand --type 'With --map: transmission type (1..240 on SYNC, 254/255 by event)'
            cand --interval 'Through an EPOS2: how often to poll each PDO'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --start 'Put the node in Operational, and back in its former state at the end'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;monitor'= {
            cand --node 'Only frames of this node (repeatable); NMT, SYNC and LSS are always shown'
            cand --duration 'Stop after this long'
            cand --count 'Stop after this many frames'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;config'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
            cand dump 'Read every readable object of a node into a DCF'
            cand diff 'Show where a node differs from a DCF''s ParameterValues'
            cand apply 'Make a node match a DCF: write only what differs, safely, and prove it'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;config;dump'= {
            cand --out 'Write the DCF here instead of standard output'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;config;diff'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --check 'Exit 6 when anything differs'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;config;apply'= {
            cand --store-timeout 'How long the device may take to store'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand --dry-run 'Show what would be written, write nothing'
            cand --store 'Store the parameters (0x1010:1) when everything is written'
            cand --verify 'Read every written object back (exit 6 when one differs)'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;config;help'= {
            cand dump 'Read every readable object of a node into a DCF'
            cand diff 'Show where a node differs from a DCF''s ParameterValues'
            cand apply 'Make a node match a DCF: write only what differs, safely, and prove it'
            cand help 'Print this message or the help of the given subcommand(s)'
        }
        &'canctl;config;help;dump'= {
        }
        &'canctl;config;help;diff'= {
        }
        &'canctl;config;help;apply'= {
        }
        &'canctl;config;help;help'= {
        }
        &'canctl;sim'= {
            cand --socketcan 'Put the devices on this CAN interface (vcan0, can0) and answer there'
            cand --baud 'Pace bytes as a serial line at this bit rate would (10 bits a byte)'
            cand --fault 'Inject a fault: nack, crc, garbage, drop or mute, on frame N (KIND@N) or every frame (KIND@*)'
            cand --can-timeout 'How long the EPOS2 waits for an SDO answer on the CAN bus'
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
        &'canctl;settings'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
            cand -v 'Trace every frame on stderr in candump notation'
            cand --verbose 'Trace every frame on stderr in candump notation'
            cand -q 'No diagnostics or progress on stderr (errors still print)'
            cand --quiet 'No diagnostics or progress on stderr (errors still print)'
            cand -h 'Print help (see more with ''--help'')'
            cand --help 'Print help (see more with ''--help'')'
            cand -V 'Print version'
            cand --version 'Print version'
        }
        &'canctl;completions'= {
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand --bus 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)'
            cand --timeout 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s'
            cand --format 'Output format'
            cand --eds 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it'
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
            cand lss 'Node-ids and bit rates over LSS (CiA 305): find, set, store, assign'
            cand store 'Save parameters to non-volatile memory (writes ''save'' to 0x1010)'
            cand restore 'Bring back default parameters (writes ''load'' to 0x1011)'
            cand stream-pdo 'Stream a node''s transmit PDOs, decoded'
            cand monitor 'Watch the bus: every frame decoded, as it happens'
            cand config 'Configuration files: dump a node to a DCF, compare, apply'
            cand sim 'Run the simulated network on a CAN interface or behind a serial link, or manage its state'
            cand settings 'Show the settings in force and where each comes from (flags, CANCTL_BUS, canctl.toml)'
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
        &'canctl;help;lss'= {
            cand inquire 'Read a device''s identity and node-id'
            cand set-id 'Give a device a node-id (1..127; 255 takes it away)'
            cand set-baud 'Configure a device''s bit rate (takes effect at `lss activate`, or stored and reset)'
            cand activate 'Switch configured bit rates on (every device in configuration state at once)'
            cand store 'Make a device keep its LSS node-id and bit rate across power cycles'
            cand fastscan 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)'
            cand assign 'Give every device without a node-id the next free one, and store it'
        }
        &'canctl;help;lss;inquire'= {
        }
        &'canctl;help;lss;set-id'= {
        }
        &'canctl;help;lss;set-baud'= {
        }
        &'canctl;help;lss;activate'= {
        }
        &'canctl;help;lss;store'= {
        }
        &'canctl;help;lss;fastscan'= {
        }
        &'canctl;help;lss;assign'= {
        }
        &'canctl;help;store'= {
        }
        &'canctl;help;restore'= {
        }
        &'canctl;help;stream-pdo'= {
        }
        &'canctl;help;monitor'= {
        }
        &'canctl;help;config'= {
            cand dump 'Read every readable object of a node into a DCF'
            cand diff 'Show where a node differs from a DCF''s ParameterValues'
            cand apply 'Make a node match a DCF: write only what differs, safely, and prove it'
        }
        &'canctl;help;config;dump'= {
        }
        &'canctl;help;config;diff'= {
        }
        &'canctl;help;config;apply'= {
        }
        &'canctl;help;sim'= {
            cand reset 'Forget the simulated network''s saved state: devices start as built'
        }
        &'canctl;help;sim;reset'= {
        }
        &'canctl;help;settings'= {
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
