complete --keep-order --exclusive --command canctl --arguments "(COMPLETE=fish canctl -- (commandline --current-process --tokenize --cut-at-cursor) (commandline --current-token))"
