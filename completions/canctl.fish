# Print an optspec for argparse to handle cmd's options that are independent of any subcommand.
function __fish_canctl_global_optspecs
    string join \n bus= timeout= format= eds= v/verbose q/quiet h/help V/version
end

function __fish_canctl_needs_command
    # Figure out if the current invocation already has a command.
    set -l cmd (commandline -opc)
    set -e cmd[1]
    argparse -s (__fish_canctl_global_optspecs) -- $cmd 2>/dev/null
    or return
    if set -q argv[1]
        # Also print the command, so this can be used to figure out what it is.
        echo $argv[1]
        return 1
    end
    return 0
end

function __fish_canctl_using_subcommand
    set -l cmd (__fish_canctl_needs_command)
    test -z "$cmd"
    and return 1
    contains -- $cmd[1] $argv
end

complete -c canctl -n "__fish_canctl_needs_command" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_needs_command" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_needs_command" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_needs_command" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_needs_command" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_needs_command" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_needs_command" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_needs_command" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "scan" -d 'Find every node on the bus'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "sdo" -d 'Read and write objects (SDO)'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "nmt" -d 'Start, stop and reset nodes, or ask their NMT state'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "lss" -d 'Node-ids and bit rates over LSS (CiA 305): find, set, store, assign'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "store" -d 'Save parameters to non-volatile memory (writes \'save\' to 0x1010)'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "restore" -d 'Bring back default parameters (writes \'load\' to 0x1011)'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "stream-pdo" -d 'Stream a node\'s transmit PDOs, decoded'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "monitor" -d 'Watch the bus: every frame decoded, as it happens'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "config" -d 'Configuration files: dump a node to a DCF, compare, apply'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "sim" -d 'Run the simulated network on a CAN interface or behind a serial link, or manage its state'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "settings" -d 'Show the settings in force and where each comes from (flags, CANCTL_BUS, canctl.toml)'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "completions" -d 'Print a shell completion script'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "man" -d 'Print the man page, or write every page to a directory'
complete -c canctl -n "__fish_canctl_needs_command" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand scan" -l window -d 'How long to wait for answers to the probes' -r
complete -c canctl -n "__fish_canctl_using_subcommand scan" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand scan" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand scan" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand scan" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand scan" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand scan" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand scan" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand scan" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -f -a "read" -d 'Read an object (SDO upload)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -f -a "write" -d 'Write an object (SDO download)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and not __fish_seen_subcommand_from read write help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -s t -l type -d 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -l out -d 'Write the raw bytes to this file instead of printing them' -r -F
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -l no-block -d 'Never use block transfer (segmented instead)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from read" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -s t -l type -d 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -l verify -d 'Read the object back and compare (exit 6 when it differs)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -l no-block -d 'Never use block transfer (segmented instead)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from write" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from help" -f -a "read" -d 'Read an object (SDO upload)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from help" -f -a "write" -d 'Write an object (SDO download)'
complete -c canctl -n "__fish_canctl_using_subcommand sdo; and __fish_seen_subcommand_from help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -f -a "start" -d 'Put a node (or all) in Operational'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -f -a "stop" -d 'Put a node (or all) in Stopped'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -f -a "preop" -d 'Put a node (or all) in Pre-operational'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -f -a "reset" -d 'Reset a node\'s application (or all nodes\') and wait for the boot-up'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -f -a "reset-comm" -d 'Reset a node\'s communication (or all nodes\') and wait for the boot-up'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -f -a "state" -d 'Report a node\'s NMT state, from its heartbeat or by node guarding'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and not __fish_seen_subcommand_from start stop preop reset reset-comm state help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from start" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from start" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from start" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from start" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from start" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from start" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from start" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from start" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from stop" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from stop" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from stop" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from stop" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from stop" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from stop" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from stop" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from stop" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from preop" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from preop" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from preop" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from preop" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from preop" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from preop" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from preop" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from preop" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -l wait -d 'How long to wait for boot-up messages' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -l wait -d 'How long to wait for boot-up messages' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from reset-comm" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -l listen -d 'How long to listen for a heartbeat before asking by node guarding' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from state" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from help" -f -a "start" -d 'Put a node (or all) in Operational'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from help" -f -a "stop" -d 'Put a node (or all) in Stopped'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from help" -f -a "preop" -d 'Put a node (or all) in Pre-operational'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from help" -f -a "reset" -d 'Reset a node\'s application (or all nodes\') and wait for the boot-up'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from help" -f -a "reset-comm" -d 'Reset a node\'s communication (or all nodes\') and wait for the boot-up'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from help" -f -a "state" -d 'Report a node\'s NMT state, from its heartbeat or by node guarding'
complete -c canctl -n "__fish_canctl_using_subcommand nmt; and __fish_seen_subcommand_from help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -f -a "inquire" -d 'Read a device\'s identity and node-id'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -f -a "set-id" -d 'Give a device a node-id (1..127; 255 takes it away)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -f -a "set-baud" -d 'Configure a device\'s bit rate (takes effect at `lss activate`, or stored and reset)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -f -a "activate" -d 'Switch configured bit rates on (every device in configuration state at once)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -f -a "store" -d 'Make a device keep its LSS node-id and bit rate across power cycles'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -f -a "fastscan" -d 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -f -a "assign" -d 'Give every device without a node-id the next free one, and store it'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and not __fish_seen_subcommand_from inquire set-id set-baud activate store fastscan assign help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -l identity -d 'The device\'s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -l node -d '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -l global -d 'Every LSS device on the bus at once (a broadcast)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from inquire" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -l identity -d 'The device\'s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -l node -d '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -l global -d 'Every LSS device on the bus at once (a broadcast)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-id" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -l identity -d 'The device\'s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -l node -d '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -l global -d 'Every LSS device on the bus at once (a broadcast)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from set-baud" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -l delay -d 'Switch delay in ms: the devices wait this long, switch, and wait as long again' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -l identity -d 'The device\'s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -l node -d '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -l global -d 'Every LSS device on the bus at once (a broadcast)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from activate" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -l identity -d 'The device\'s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -l node -d '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -l global -d 'Every LSS device on the bus at once (a broadcast)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from store" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -l step -d 'How long each fastscan step waits for an answer' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -l node -d 'Refused: an EPOS2 reached directly (node 0) has no LSS' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from fastscan" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -l start -d 'The first node-id to give' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -l step -d 'How long each fastscan step waits for an answer' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -l node -d 'Refused: an EPOS2 reached directly (node 0) has no LSS' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -l no-store -d 'Do not store the node-ids (they are lost at power-off)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from assign" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from help" -f -a "inquire" -d 'Read a device\'s identity and node-id'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from help" -f -a "set-id" -d 'Give a device a node-id (1..127; 255 takes it away)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from help" -f -a "set-baud" -d 'Configure a device\'s bit rate (takes effect at `lss activate`, or stored and reset)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from help" -f -a "activate" -d 'Switch configured bit rates on (every device in configuration state at once)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from help" -f -a "store" -d 'Make a device keep its LSS node-id and bit rate across power cycles'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from help" -f -a "fastscan" -d 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from help" -f -a "assign" -d 'Give every device without a node-id the next free one, and store it'
complete -c canctl -n "__fish_canctl_using_subcommand lss; and __fish_seen_subcommand_from help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand store" -l store-timeout -d 'How long the device may take to store (flash writes take a while)' -r
complete -c canctl -n "__fish_canctl_using_subcommand store" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand store" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand store" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand store" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand store" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand store" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand store" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand store" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand restore" -l store-timeout -d 'How long the device may take to restore' -r
complete -c canctl -n "__fish_canctl_using_subcommand restore" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand restore" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand restore" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand restore" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand restore" -l reset -d 'Reset the node afterwards and wait for it to boot with the defaults'
complete -c canctl -n "__fish_canctl_using_subcommand restore" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand restore" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand restore" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand restore" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l tpdo -d 'Which TPDOs (default: every valid one of 1..4)' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l count -d 'Stop after this many records' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l duration -d 'Stop after this long' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l sync -d 'Send SYNC at this period (for synchronous PDOs, transmission types 0..240)' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l map -d 'Map these objects into the (first) TPDO for this session: 6064:0,606C:0' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l event -d 'With --map: event timer in ms' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l type -d 'With --map: transmission type (1..240 on SYNC, 254/255 by event)' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l interval -d 'Through an EPOS2: how often to poll each PDO' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -l start -d 'Put the node in Operational, and back in its former state at the end'
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand stream-pdo" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -l node -d 'Only frames of this node (repeatable); NMT, SYNC and LSS are always shown' -r
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -l duration -d 'Stop after this long' -r
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -l count -d 'Stop after this many frames' -r
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand monitor" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -f -a "dump" -d 'Read every readable object of a node into a DCF'
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -f -a "diff" -d 'Show where a node differs from a DCF\'s ParameterValues'
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -f -a "apply" -d 'Make a node match a DCF: write only what differs, safely, and prove it'
complete -c canctl -n "__fish_canctl_using_subcommand config; and not __fish_seen_subcommand_from dump diff apply help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -l out -d 'Write the DCF here instead of standard output' -r -F
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from dump" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -l check -d 'Exit 6 when anything differs'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from diff" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -l store-timeout -d 'How long the device may take to store' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -l dry-run -d 'Show what would be written, write nothing'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -l store -d 'Store the parameters (0x1010:1) when everything is written'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -l verify -d 'Read every written object back (exit 6 when one differs)'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from apply" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from help" -f -a "dump" -d 'Read every readable object of a node into a DCF'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from help" -f -a "diff" -d 'Show where a node differs from a DCF\'s ParameterValues'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from help" -f -a "apply" -d 'Make a node match a DCF: write only what differs, safely, and prove it'
complete -c canctl -n "__fish_canctl_using_subcommand config; and __fish_seen_subcommand_from help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l socketcan -d 'Put the devices on this CAN interface (vcan0, can0) and answer there' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l baud -d 'Pace bytes as a serial line at this bit rate would (10 bits a byte)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l fault -d 'Inject a fault: nack, crc, garbage, drop or mute, on frame N (KIND@N) or every frame (KIND@*)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l can-timeout -d 'How long the EPOS2 waits for an SDO answer on the CAN bus' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l epos2-rs232 -d 'Serve an EPOS2 speaking the RS232 protocol (with the \'O\'/\'F\' handshake)'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -l epos2-usb -d 'Serve an EPOS2 speaking the USB protocol (DLE/STX framing)'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -f -a "reset" -d 'Forget the simulated network\'s saved state: devices start as built'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and not __fish_seen_subcommand_from reset help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from reset" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from reset" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from reset" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from reset" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from reset" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from reset" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from reset" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from reset" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from help" -f -a "reset" -d 'Forget the simulated network\'s saved state: devices start as built'
complete -c canctl -n "__fish_canctl_using_subcommand sim; and __fish_seen_subcommand_from help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand settings" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand settings" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand settings" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand settings" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand settings" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand settings" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand settings" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand settings" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand completions" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand completions" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand completions" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand completions" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand completions" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand completions" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand completions" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand completions" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand man" -l out -d 'Write canctl.1 and one page per subcommand into this directory' -r -F
complete -c canctl -n "__fish_canctl_using_subcommand man" -l bus -d 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file\'s)' -r
complete -c canctl -n "__fish_canctl_using_subcommand man" -l timeout -d 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file\'s' -r
complete -c canctl -n "__fish_canctl_using_subcommand man" -l format -d 'Output format' -r -f -a "human\t'Tables and sentences for people'
json\t'One JSON document per command (JSON lines for streams)'
csv\t'A header row and one row per record'"
complete -c canctl -n "__fish_canctl_using_subcommand man" -l eds -d 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it' -r
complete -c canctl -n "__fish_canctl_using_subcommand man" -s v -l verbose -d 'Trace every frame on stderr in candump notation'
complete -c canctl -n "__fish_canctl_using_subcommand man" -s q -l quiet -d 'No diagnostics or progress on stderr (errors still print)'
complete -c canctl -n "__fish_canctl_using_subcommand man" -s h -l help -d 'Print help (see more with \'--help\')'
complete -c canctl -n "__fish_canctl_using_subcommand man" -s V -l version -d 'Print version'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "scan" -d 'Find every node on the bus'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "sdo" -d 'Read and write objects (SDO)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "nmt" -d 'Start, stop and reset nodes, or ask their NMT state'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "lss" -d 'Node-ids and bit rates over LSS (CiA 305): find, set, store, assign'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "store" -d 'Save parameters to non-volatile memory (writes \'save\' to 0x1010)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "restore" -d 'Bring back default parameters (writes \'load\' to 0x1011)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "stream-pdo" -d 'Stream a node\'s transmit PDOs, decoded'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "monitor" -d 'Watch the bus: every frame decoded, as it happens'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "config" -d 'Configuration files: dump a node to a DCF, compare, apply'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "sim" -d 'Run the simulated network on a CAN interface or behind a serial link, or manage its state'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "settings" -d 'Show the settings in force and where each comes from (flags, CANCTL_BUS, canctl.toml)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "completions" -d 'Print a shell completion script'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "man" -d 'Print the man page, or write every page to a directory'
complete -c canctl -n "__fish_canctl_using_subcommand help; and not __fish_seen_subcommand_from scan sdo nmt lss store restore stream-pdo monitor config sim settings completions man help" -f -a "help" -d 'Print this message or the help of the given subcommand(s)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from sdo" -f -a "read" -d 'Read an object (SDO upload)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from sdo" -f -a "write" -d 'Write an object (SDO download)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from nmt" -f -a "start" -d 'Put a node (or all) in Operational'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from nmt" -f -a "stop" -d 'Put a node (or all) in Stopped'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from nmt" -f -a "preop" -d 'Put a node (or all) in Pre-operational'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from nmt" -f -a "reset" -d 'Reset a node\'s application (or all nodes\') and wait for the boot-up'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from nmt" -f -a "reset-comm" -d 'Reset a node\'s communication (or all nodes\') and wait for the boot-up'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from nmt" -f -a "state" -d 'Report a node\'s NMT state, from its heartbeat or by node guarding'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from lss" -f -a "inquire" -d 'Read a device\'s identity and node-id'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from lss" -f -a "set-id" -d 'Give a device a node-id (1..127; 255 takes it away)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from lss" -f -a "set-baud" -d 'Configure a device\'s bit rate (takes effect at `lss activate`, or stored and reset)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from lss" -f -a "activate" -d 'Switch configured bit rates on (every device in configuration state at once)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from lss" -f -a "store" -d 'Make a device keep its LSS node-id and bit rate across power cycles'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from lss" -f -a "fastscan" -d 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from lss" -f -a "assign" -d 'Give every device without a node-id the next free one, and store it'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from config" -f -a "dump" -d 'Read every readable object of a node into a DCF'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from config" -f -a "diff" -d 'Show where a node differs from a DCF\'s ParameterValues'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from config" -f -a "apply" -d 'Make a node match a DCF: write only what differs, safely, and prove it'
complete -c canctl -n "__fish_canctl_using_subcommand help; and __fish_seen_subcommand_from sim" -f -a "reset" -d 'Forget the simulated network\'s saved state: devices start as built'
