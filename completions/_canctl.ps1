
using namespace System.Management.Automation
using namespace System.Management.Automation.Language

Register-ArgumentCompleter -Native -CommandName 'canctl' -ScriptBlock {
    param($wordToComplete, $commandAst, $cursorPosition)

    $commandElements = $commandAst.CommandElements
    $command = @(
        'canctl'
        for ($i = 1; $i -lt $commandElements.Count; $i++) {
            $element = $commandElements[$i]
            if ($element -isnot [StringConstantExpressionAst] -or
                $element.StringConstantType -ne [StringConstantType]::BareWord -or
                $element.Value.StartsWith('-') -or
                $element.Value -eq $wordToComplete) {
                break
        }
        $element.Value
    }) -join ';'

    $completions = @(switch ($command) {
        'canctl' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('scan', 'scan', [CompletionResultType]::ParameterValue, 'Find every node on the bus')
            [CompletionResult]::new('sdo', 'sdo', [CompletionResultType]::ParameterValue, 'Read and write objects (SDO)')
            [CompletionResult]::new('nmt', 'nmt', [CompletionResultType]::ParameterValue, 'Start, stop and reset nodes, or ask their NMT state')
            [CompletionResult]::new('lss', 'lss', [CompletionResultType]::ParameterValue, 'Node-ids and bit rates over LSS (CiA 305): find, set, store, assign')
            [CompletionResult]::new('store', 'store', [CompletionResultType]::ParameterValue, 'Save parameters to non-volatile memory (writes ''save'' to 0x1010)')
            [CompletionResult]::new('restore', 'restore', [CompletionResultType]::ParameterValue, 'Bring back default parameters (writes ''load'' to 0x1011)')
            [CompletionResult]::new('stream-pdo', 'stream-pdo', [CompletionResultType]::ParameterValue, 'Stream a node''s transmit PDOs, decoded')
            [CompletionResult]::new('monitor', 'monitor', [CompletionResultType]::ParameterValue, 'Watch the bus: every frame decoded, as it happens')
            [CompletionResult]::new('config', 'config', [CompletionResultType]::ParameterValue, 'Configuration files: dump a node to a DCF, compare, apply')
            [CompletionResult]::new('sim', 'sim', [CompletionResultType]::ParameterValue, 'Run the simulated network on a CAN interface or behind a serial link, or manage its state')
            [CompletionResult]::new('settings', 'settings', [CompletionResultType]::ParameterValue, 'Show the settings in force and where each comes from (flags, CANCTL_BUS, canctl.toml)')
            [CompletionResult]::new('completions', 'completions', [CompletionResultType]::ParameterValue, 'Print a shell completion script')
            [CompletionResult]::new('man', 'man', [CompletionResultType]::ParameterValue, 'Print the man page, or write every page to a directory')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;scan' {
            [CompletionResult]::new('--window', '--window', [CompletionResultType]::ParameterName, 'How long to wait for answers to the probes')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;sdo' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('read', 'read', [CompletionResultType]::ParameterValue, 'Read an object (SDO upload)')
            [CompletionResult]::new('write', 'write', [CompletionResultType]::ParameterValue, 'Write an object (SDO download)')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;sdo;read' {
            [CompletionResult]::new('-t', '-t', [CompletionResultType]::ParameterName, 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary''s)')
            [CompletionResult]::new('--type', '--type', [CompletionResultType]::ParameterName, 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary''s)')
            [CompletionResult]::new('--out', '--out', [CompletionResultType]::ParameterName, 'Write the raw bytes to this file instead of printing them')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--no-block', '--no-block', [CompletionResultType]::ParameterName, 'Never use block transfer (segmented instead)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;sdo;write' {
            [CompletionResult]::new('-t', '-t', [CompletionResultType]::ParameterName, 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary''s)')
            [CompletionResult]::new('--type', '--type', [CompletionResultType]::ParameterName, 'Data type: b u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs os d (default: the dictionary''s)')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--verify', '--verify', [CompletionResultType]::ParameterName, 'Read the object back and compare (exit 6 when it differs)')
            [CompletionResult]::new('--no-block', '--no-block', [CompletionResultType]::ParameterName, 'Never use block transfer (segmented instead)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;sdo;help' {
            [CompletionResult]::new('read', 'read', [CompletionResultType]::ParameterValue, 'Read an object (SDO upload)')
            [CompletionResult]::new('write', 'write', [CompletionResultType]::ParameterValue, 'Write an object (SDO download)')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;sdo;help;read' {
            break
        }
        'canctl;sdo;help;write' {
            break
        }
        'canctl;sdo;help;help' {
            break
        }
        'canctl;nmt' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('start', 'start', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Operational')
            [CompletionResult]::new('stop', 'stop', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Stopped')
            [CompletionResult]::new('preop', 'preop', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Pre-operational')
            [CompletionResult]::new('reset', 'reset', [CompletionResultType]::ParameterValue, 'Reset a node''s application (or all nodes'') and wait for the boot-up')
            [CompletionResult]::new('reset-comm', 'reset-comm', [CompletionResultType]::ParameterValue, 'Reset a node''s communication (or all nodes'') and wait for the boot-up')
            [CompletionResult]::new('state', 'state', [CompletionResultType]::ParameterValue, 'Report a node''s NMT state, from its heartbeat or by node guarding')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;nmt;start' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;nmt;stop' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;nmt;preop' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;nmt;reset' {
            [CompletionResult]::new('--wait', '--wait', [CompletionResultType]::ParameterName, 'How long to wait for boot-up messages')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;nmt;reset-comm' {
            [CompletionResult]::new('--wait', '--wait', [CompletionResultType]::ParameterName, 'How long to wait for boot-up messages')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;nmt;state' {
            [CompletionResult]::new('--listen', '--listen', [CompletionResultType]::ParameterName, 'How long to listen for a heartbeat before asking by node guarding')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;nmt;help' {
            [CompletionResult]::new('start', 'start', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Operational')
            [CompletionResult]::new('stop', 'stop', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Stopped')
            [CompletionResult]::new('preop', 'preop', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Pre-operational')
            [CompletionResult]::new('reset', 'reset', [CompletionResultType]::ParameterValue, 'Reset a node''s application (or all nodes'') and wait for the boot-up')
            [CompletionResult]::new('reset-comm', 'reset-comm', [CompletionResultType]::ParameterValue, 'Reset a node''s communication (or all nodes'') and wait for the boot-up')
            [CompletionResult]::new('state', 'state', [CompletionResultType]::ParameterValue, 'Report a node''s NMT state, from its heartbeat or by node guarding')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;nmt;help;start' {
            break
        }
        'canctl;nmt;help;stop' {
            break
        }
        'canctl;nmt;help;preop' {
            break
        }
        'canctl;nmt;help;reset' {
            break
        }
        'canctl;nmt;help;reset-comm' {
            break
        }
        'canctl;nmt;help;state' {
            break
        }
        'canctl;nmt;help;help' {
            break
        }
        'canctl;lss' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('inquire', 'inquire', [CompletionResultType]::ParameterValue, 'Read a device''s identity and node-id')
            [CompletionResult]::new('set-id', 'set-id', [CompletionResultType]::ParameterValue, 'Give a device a node-id (1..127; 255 takes it away)')
            [CompletionResult]::new('set-baud', 'set-baud', [CompletionResultType]::ParameterValue, 'Configure a device''s bit rate (takes effect at `lss activate`, or stored and reset)')
            [CompletionResult]::new('activate', 'activate', [CompletionResultType]::ParameterValue, 'Switch configured bit rates on (every device in configuration state at once)')
            [CompletionResult]::new('store', 'store', [CompletionResultType]::ParameterValue, 'Make a device keep its LSS node-id and bit rate across power cycles')
            [CompletionResult]::new('fastscan', 'fastscan', [CompletionResultType]::ParameterValue, 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)')
            [CompletionResult]::new('assign', 'assign', [CompletionResultType]::ParameterValue, 'Give every device without a node-id the next free one, and store it')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;lss;inquire' {
            [CompletionResult]::new('--identity', '--identity', [CompletionResultType]::ParameterName, 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)')
            [CompletionResult]::new('--node', '--node', [CompletionResultType]::ParameterName, '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--global', '--global', [CompletionResultType]::ParameterName, 'Every LSS device on the bus at once (a broadcast)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;lss;set-id' {
            [CompletionResult]::new('--identity', '--identity', [CompletionResultType]::ParameterName, 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)')
            [CompletionResult]::new('--node', '--node', [CompletionResultType]::ParameterName, '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--global', '--global', [CompletionResultType]::ParameterName, 'Every LSS device on the bus at once (a broadcast)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;lss;set-baud' {
            [CompletionResult]::new('--identity', '--identity', [CompletionResultType]::ParameterName, 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)')
            [CompletionResult]::new('--node', '--node', [CompletionResultType]::ParameterName, '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--global', '--global', [CompletionResultType]::ParameterName, 'Every LSS device on the bus at once (a broadcast)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;lss;activate' {
            [CompletionResult]::new('--delay', '--delay', [CompletionResultType]::ParameterName, 'Switch delay in ms: the devices wait this long, switch, and wait as long again')
            [CompletionResult]::new('--identity', '--identity', [CompletionResultType]::ParameterName, 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)')
            [CompletionResult]::new('--node', '--node', [CompletionResultType]::ParameterName, '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--global', '--global', [CompletionResultType]::ParameterName, 'Every LSS device on the bus at once (a broadcast)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;lss;store' {
            [CompletionResult]::new('--identity', '--identity', [CompletionResultType]::ParameterName, 'The device''s LSS address: VENDOR:PRODUCT:REVISION:SERIAL (decimal or 0x hex)')
            [CompletionResult]::new('--node', '--node', [CompletionResultType]::ParameterName, '0: the EPOS2 on an epos2-rs232/epos2-usb bus, through its own objects (it has no LSS)')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--global', '--global', [CompletionResultType]::ParameterName, 'Every LSS device on the bus at once (a broadcast)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;lss;fastscan' {
            [CompletionResult]::new('--step', '--step', [CompletionResultType]::ParameterName, 'How long each fastscan step waits for an answer')
            [CompletionResult]::new('--node', '--node', [CompletionResultType]::ParameterName, 'Refused: an EPOS2 reached directly (node 0) has no LSS')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;lss;assign' {
            [CompletionResult]::new('--start', '--start', [CompletionResultType]::ParameterName, 'The first node-id to give')
            [CompletionResult]::new('--step', '--step', [CompletionResultType]::ParameterName, 'How long each fastscan step waits for an answer')
            [CompletionResult]::new('--node', '--node', [CompletionResultType]::ParameterName, 'Refused: an EPOS2 reached directly (node 0) has no LSS')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--no-store', '--no-store', [CompletionResultType]::ParameterName, 'Do not store the node-ids (they are lost at power-off)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;lss;help' {
            [CompletionResult]::new('inquire', 'inquire', [CompletionResultType]::ParameterValue, 'Read a device''s identity and node-id')
            [CompletionResult]::new('set-id', 'set-id', [CompletionResultType]::ParameterValue, 'Give a device a node-id (1..127; 255 takes it away)')
            [CompletionResult]::new('set-baud', 'set-baud', [CompletionResultType]::ParameterValue, 'Configure a device''s bit rate (takes effect at `lss activate`, or stored and reset)')
            [CompletionResult]::new('activate', 'activate', [CompletionResultType]::ParameterValue, 'Switch configured bit rates on (every device in configuration state at once)')
            [CompletionResult]::new('store', 'store', [CompletionResultType]::ParameterValue, 'Make a device keep its LSS node-id and bit rate across power cycles')
            [CompletionResult]::new('fastscan', 'fastscan', [CompletionResultType]::ParameterValue, 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)')
            [CompletionResult]::new('assign', 'assign', [CompletionResultType]::ParameterValue, 'Give every device without a node-id the next free one, and store it')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;lss;help;inquire' {
            break
        }
        'canctl;lss;help;set-id' {
            break
        }
        'canctl;lss;help;set-baud' {
            break
        }
        'canctl;lss;help;activate' {
            break
        }
        'canctl;lss;help;store' {
            break
        }
        'canctl;lss;help;fastscan' {
            break
        }
        'canctl;lss;help;assign' {
            break
        }
        'canctl;lss;help;help' {
            break
        }
        'canctl;store' {
            [CompletionResult]::new('--store-timeout', '--store-timeout', [CompletionResultType]::ParameterName, 'How long the device may take to store (flash writes take a while)')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;restore' {
            [CompletionResult]::new('--store-timeout', '--store-timeout', [CompletionResultType]::ParameterName, 'How long the device may take to restore')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--reset', '--reset', [CompletionResultType]::ParameterName, 'Reset the node afterwards and wait for it to boot with the defaults')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;stream-pdo' {
            [CompletionResult]::new('--tpdo', '--tpdo', [CompletionResultType]::ParameterName, 'Which TPDOs (default: every valid one of 1..4)')
            [CompletionResult]::new('--count', '--count', [CompletionResultType]::ParameterName, 'Stop after this many records')
            [CompletionResult]::new('--duration', '--duration', [CompletionResultType]::ParameterName, 'Stop after this long')
            [CompletionResult]::new('--sync', '--sync', [CompletionResultType]::ParameterName, 'Send SYNC at this period (for synchronous PDOs, transmission types 0..240)')
            [CompletionResult]::new('--map', '--map', [CompletionResultType]::ParameterName, 'Map these objects into the (first) TPDO for this session: 6064:0,606C:0')
            [CompletionResult]::new('--event', '--event', [CompletionResultType]::ParameterName, 'With --map: event timer in ms')
            [CompletionResult]::new('--type', '--type', [CompletionResultType]::ParameterName, 'With --map: transmission type (1..240 on SYNC, 254/255 by event)')
            [CompletionResult]::new('--interval', '--interval', [CompletionResultType]::ParameterName, 'Through an EPOS2: how often to poll each PDO')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--start', '--start', [CompletionResultType]::ParameterName, 'Put the node in Operational, and back in its former state at the end')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;monitor' {
            [CompletionResult]::new('--node', '--node', [CompletionResultType]::ParameterName, 'Only frames of this node (repeatable); NMT, SYNC and LSS are always shown')
            [CompletionResult]::new('--duration', '--duration', [CompletionResultType]::ParameterName, 'Stop after this long')
            [CompletionResult]::new('--count', '--count', [CompletionResultType]::ParameterName, 'Stop after this many frames')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;config' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('dump', 'dump', [CompletionResultType]::ParameterValue, 'Read every readable object of a node into a DCF')
            [CompletionResult]::new('diff', 'diff', [CompletionResultType]::ParameterValue, 'Show where a node differs from a DCF''s ParameterValues')
            [CompletionResult]::new('apply', 'apply', [CompletionResultType]::ParameterValue, 'Make a node match a DCF: write only what differs, safely, and prove it')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;config;dump' {
            [CompletionResult]::new('--out', '--out', [CompletionResultType]::ParameterName, 'Write the DCF here instead of standard output')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;config;diff' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--check', '--check', [CompletionResultType]::ParameterName, 'Exit 6 when anything differs')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;config;apply' {
            [CompletionResult]::new('--store-timeout', '--store-timeout', [CompletionResultType]::ParameterName, 'How long the device may take to store')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--dry-run', '--dry-run', [CompletionResultType]::ParameterName, 'Show what would be written, write nothing')
            [CompletionResult]::new('--store', '--store', [CompletionResultType]::ParameterName, 'Store the parameters (0x1010:1) when everything is written')
            [CompletionResult]::new('--verify', '--verify', [CompletionResultType]::ParameterName, 'Read every written object back (exit 6 when one differs)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;config;help' {
            [CompletionResult]::new('dump', 'dump', [CompletionResultType]::ParameterValue, 'Read every readable object of a node into a DCF')
            [CompletionResult]::new('diff', 'diff', [CompletionResultType]::ParameterValue, 'Show where a node differs from a DCF''s ParameterValues')
            [CompletionResult]::new('apply', 'apply', [CompletionResultType]::ParameterValue, 'Make a node match a DCF: write only what differs, safely, and prove it')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;config;help;dump' {
            break
        }
        'canctl;config;help;diff' {
            break
        }
        'canctl;config;help;apply' {
            break
        }
        'canctl;config;help;help' {
            break
        }
        'canctl;sim' {
            [CompletionResult]::new('--socketcan', '--socketcan', [CompletionResultType]::ParameterName, 'Put the devices on this CAN interface (vcan0, can0) and answer there')
            [CompletionResult]::new('--baud', '--baud', [CompletionResultType]::ParameterName, 'Pace bytes as a serial line at this bit rate would (10 bits a byte)')
            [CompletionResult]::new('--fault', '--fault', [CompletionResultType]::ParameterName, 'Inject a fault: nack, crc, garbage, drop or mute, on frame N (KIND@N) or every frame (KIND@*)')
            [CompletionResult]::new('--can-timeout', '--can-timeout', [CompletionResultType]::ParameterName, 'How long the EPOS2 waits for an SDO answer on the CAN bus')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('--epos2-rs232', '--epos2-rs232', [CompletionResultType]::ParameterName, 'Serve an EPOS2 speaking the RS232 protocol (with the ''O''/''F'' handshake)')
            [CompletionResult]::new('--epos2-usb', '--epos2-usb', [CompletionResultType]::ParameterName, 'Serve an EPOS2 speaking the USB protocol (DLE/STX framing)')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('reset', 'reset', [CompletionResultType]::ParameterValue, 'Forget the simulated network''s saved state: devices start as built')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;sim;reset' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;sim;help' {
            [CompletionResult]::new('reset', 'reset', [CompletionResultType]::ParameterValue, 'Forget the simulated network''s saved state: devices start as built')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;sim;help;reset' {
            break
        }
        'canctl;sim;help;help' {
            break
        }
        'canctl;settings' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;completions' {
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;man' {
            [CompletionResult]::new('--out', '--out', [CompletionResultType]::ParameterName, 'Write canctl.1 and one page per subcommand into this directory')
            [CompletionResult]::new('--bus', '--bus', [CompletionResultType]::ParameterName, 'The bus: sim, sim:STATEFILE, socketcan:can0 (or can0), epos2-rs232:/dev/ttyS0?baud=115200, epos2-usb:/dev/ttyUSB0 (default: CANCTL_BUS, else the settings file''s)')
            [CompletionResult]::new('--timeout', '--timeout', [CompletionResultType]::ParameterName, 'How long to wait for each answer: 500ms, 2s, 1.5s (a bare number is milliseconds); default 500ms, or the settings file''s')
            [CompletionResult]::new('--format', '--format', [CompletionResultType]::ParameterName, 'Output format')
            [CompletionResult]::new('--eds', '--eds', [CompletionResultType]::ParameterName, 'An EDS or DCF describing node NODE, or every node without NODE= (repeatable): object names, types and ranges come from it')
            [CompletionResult]::new('-v', '-v', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('--verbose', '--verbose', [CompletionResultType]::ParameterName, 'Trace every frame on stderr in candump notation')
            [CompletionResult]::new('-q', '-q', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('--quiet', '--quiet', [CompletionResultType]::ParameterName, 'No diagnostics or progress on stderr (errors still print)')
            [CompletionResult]::new('-h', '-h', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('--help', '--help', [CompletionResultType]::ParameterName, 'Print help (see more with ''--help'')')
            [CompletionResult]::new('-V', '-V ', [CompletionResultType]::ParameterName, 'Print version')
            [CompletionResult]::new('--version', '--version', [CompletionResultType]::ParameterName, 'Print version')
            break
        }
        'canctl;help' {
            [CompletionResult]::new('scan', 'scan', [CompletionResultType]::ParameterValue, 'Find every node on the bus')
            [CompletionResult]::new('sdo', 'sdo', [CompletionResultType]::ParameterValue, 'Read and write objects (SDO)')
            [CompletionResult]::new('nmt', 'nmt', [CompletionResultType]::ParameterValue, 'Start, stop and reset nodes, or ask their NMT state')
            [CompletionResult]::new('lss', 'lss', [CompletionResultType]::ParameterValue, 'Node-ids and bit rates over LSS (CiA 305): find, set, store, assign')
            [CompletionResult]::new('store', 'store', [CompletionResultType]::ParameterValue, 'Save parameters to non-volatile memory (writes ''save'' to 0x1010)')
            [CompletionResult]::new('restore', 'restore', [CompletionResultType]::ParameterValue, 'Bring back default parameters (writes ''load'' to 0x1011)')
            [CompletionResult]::new('stream-pdo', 'stream-pdo', [CompletionResultType]::ParameterValue, 'Stream a node''s transmit PDOs, decoded')
            [CompletionResult]::new('monitor', 'monitor', [CompletionResultType]::ParameterValue, 'Watch the bus: every frame decoded, as it happens')
            [CompletionResult]::new('config', 'config', [CompletionResultType]::ParameterValue, 'Configuration files: dump a node to a DCF, compare, apply')
            [CompletionResult]::new('sim', 'sim', [CompletionResultType]::ParameterValue, 'Run the simulated network on a CAN interface or behind a serial link, or manage its state')
            [CompletionResult]::new('settings', 'settings', [CompletionResultType]::ParameterValue, 'Show the settings in force and where each comes from (flags, CANCTL_BUS, canctl.toml)')
            [CompletionResult]::new('completions', 'completions', [CompletionResultType]::ParameterValue, 'Print a shell completion script')
            [CompletionResult]::new('man', 'man', [CompletionResultType]::ParameterValue, 'Print the man page, or write every page to a directory')
            [CompletionResult]::new('help', 'help', [CompletionResultType]::ParameterValue, 'Print this message or the help of the given subcommand(s)')
            break
        }
        'canctl;help;scan' {
            break
        }
        'canctl;help;sdo' {
            [CompletionResult]::new('read', 'read', [CompletionResultType]::ParameterValue, 'Read an object (SDO upload)')
            [CompletionResult]::new('write', 'write', [CompletionResultType]::ParameterValue, 'Write an object (SDO download)')
            break
        }
        'canctl;help;sdo;read' {
            break
        }
        'canctl;help;sdo;write' {
            break
        }
        'canctl;help;nmt' {
            [CompletionResult]::new('start', 'start', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Operational')
            [CompletionResult]::new('stop', 'stop', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Stopped')
            [CompletionResult]::new('preop', 'preop', [CompletionResultType]::ParameterValue, 'Put a node (or all) in Pre-operational')
            [CompletionResult]::new('reset', 'reset', [CompletionResultType]::ParameterValue, 'Reset a node''s application (or all nodes'') and wait for the boot-up')
            [CompletionResult]::new('reset-comm', 'reset-comm', [CompletionResultType]::ParameterValue, 'Reset a node''s communication (or all nodes'') and wait for the boot-up')
            [CompletionResult]::new('state', 'state', [CompletionResultType]::ParameterValue, 'Report a node''s NMT state, from its heartbeat or by node guarding')
            break
        }
        'canctl;help;nmt;start' {
            break
        }
        'canctl;help;nmt;stop' {
            break
        }
        'canctl;help;nmt;preop' {
            break
        }
        'canctl;help;nmt;reset' {
            break
        }
        'canctl;help;nmt;reset-comm' {
            break
        }
        'canctl;help;nmt;state' {
            break
        }
        'canctl;help;lss' {
            [CompletionResult]::new('inquire', 'inquire', [CompletionResultType]::ParameterValue, 'Read a device''s identity and node-id')
            [CompletionResult]::new('set-id', 'set-id', [CompletionResultType]::ParameterValue, 'Give a device a node-id (1..127; 255 takes it away)')
            [CompletionResult]::new('set-baud', 'set-baud', [CompletionResultType]::ParameterValue, 'Configure a device''s bit rate (takes effect at `lss activate`, or stored and reset)')
            [CompletionResult]::new('activate', 'activate', [CompletionResultType]::ParameterValue, 'Switch configured bit rates on (every device in configuration state at once)')
            [CompletionResult]::new('store', 'store', [CompletionResultType]::ParameterValue, 'Make a device keep its LSS node-id and bit rate across power cycles')
            [CompletionResult]::new('fastscan', 'fastscan', [CompletionResultType]::ParameterValue, 'Find the identity of a device that has no node-id, bit by bit (CiA 305 fastscan)')
            [CompletionResult]::new('assign', 'assign', [CompletionResultType]::ParameterValue, 'Give every device without a node-id the next free one, and store it')
            break
        }
        'canctl;help;lss;inquire' {
            break
        }
        'canctl;help;lss;set-id' {
            break
        }
        'canctl;help;lss;set-baud' {
            break
        }
        'canctl;help;lss;activate' {
            break
        }
        'canctl;help;lss;store' {
            break
        }
        'canctl;help;lss;fastscan' {
            break
        }
        'canctl;help;lss;assign' {
            break
        }
        'canctl;help;store' {
            break
        }
        'canctl;help;restore' {
            break
        }
        'canctl;help;stream-pdo' {
            break
        }
        'canctl;help;monitor' {
            break
        }
        'canctl;help;config' {
            [CompletionResult]::new('dump', 'dump', [CompletionResultType]::ParameterValue, 'Read every readable object of a node into a DCF')
            [CompletionResult]::new('diff', 'diff', [CompletionResultType]::ParameterValue, 'Show where a node differs from a DCF''s ParameterValues')
            [CompletionResult]::new('apply', 'apply', [CompletionResultType]::ParameterValue, 'Make a node match a DCF: write only what differs, safely, and prove it')
            break
        }
        'canctl;help;config;dump' {
            break
        }
        'canctl;help;config;diff' {
            break
        }
        'canctl;help;config;apply' {
            break
        }
        'canctl;help;sim' {
            [CompletionResult]::new('reset', 'reset', [CompletionResultType]::ParameterValue, 'Forget the simulated network''s saved state: devices start as built')
            break
        }
        'canctl;help;sim;reset' {
            break
        }
        'canctl;help;settings' {
            break
        }
        'canctl;help;completions' {
            break
        }
        'canctl;help;man' {
            break
        }
        'canctl;help;help' {
            break
        }
    })

    $completions.Where{ $_.CompletionText -like "$wordToComplete*" } |
        Sort-Object -Property ListItemText
}
