# Press <Tab> in a real interactive zsh and record what it offers.
# usage: zsh -f zsh-complete.zsh FPATH_DIR OUT_FILE 'command line '
# The completion system runs in a pseudo-terminal (zpty); compadd is wrapped to append
# every candidate it is given to OUT_FILE, one per line.
zmodload zsh/zpty
zpty shell zsh -f -i
zpty -w shell "fpath=($1 \$fpath); autoload -Uz compinit; compinit -u -D"
zpty -w shell "compadd() { local -a offered; builtin compadd -O offered \"\$@\"; print -rl -- \$offered >> $2; builtin compadd \"\$@\" }"
zpty -wn shell "$3"$'\t'
for i in {1..100}; do [[ -s $2 ]] && break; sleep 0.05; done
sleep 0.2
zpty -d shell
