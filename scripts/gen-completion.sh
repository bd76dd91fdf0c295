#!/usr/bin/env bash
# gen-completion.sh TOOL — prints a bash completion for a dermis tool, made from its --help
# (through scripts/help-options.sh, the one reader of --help), for bash-completion's
# lazy-loading folder: $(PREFIX)/share/bash-completion/completions/TOOL.
# Completes every option the help documents; after an option that takes a file or folder,
# file or folder names; after one whose values are listed (sphere|quad), those values;
# after another value-taking option (N, WxH, MM), nothing; elsewhere file names.
# Needs only bash's own complete/compgen/compopt, not bash-completion's helpers.
set -euo pipefail
tool=${1:?usage: gen-completion.sh TOOL}
here=$(cd "$(dirname "$0")" && pwd)
name=$(basename "$tool")
fn=_$(echo "$name" | tr -c 'A-Za-z0-9\n' '_')
opts=() files=() dirs=() plain=() choices=()
while IFS=$'\t' read -r opt val; do
  opts+=("$opt")
  [ -z "$val" ] && continue
  case $val in
    DIR*) dirs+=("$opt") ;;
    *FILE*|*.*|MESH|PACK|OUT*|TILE*|ENV*|REF*) files+=("$opt") ;;
    *'|'*)
      if [[ $val =~ ^[a-z0-9|-]+$ ]]; then choices+=("$opt=${val//|/ }"); else plain+=("$opt"); fi ;;
    *) plain+=("$opt") ;;
  esac
done < <(bash "$here/help-options.sh" "$tool")
[[ " ${opts[*]} " == *" --version "* ]] || opts+=(--version)  # every tool answers it

join() { local IFS='|'; echo "$*"; }
echo "# bash completion for $name (generated from '$name --help' by scripts/gen-completion.sh)"
echo "$fn()"
echo "{"
echo '    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}'
echo '    case $prev in'
[ ${#files[@]} -gt 0 ] && echo "        $(join "${files[@]}")) compopt -o filenames; COMPREPLY=(\$(compgen -f -- \"\$cur\")); return ;;"
[ ${#dirs[@]} -gt 0 ] && echo "        $(join "${dirs[@]}")) compopt -o filenames; COMPREPLY=(\$(compgen -d -- \"\$cur\")); return ;;"
for c in ${choices[@]+"${choices[@]}"}; do
  echo "        ${c%%=*}) COMPREPLY=(\$(compgen -W \"${c#*=}\" -- \"\$cur\")); return ;;"
done
[ ${#plain[@]} -gt 0 ] && echo "        $(join "${plain[@]}")) COMPREPLY=(); return ;;"
echo '    esac'
echo '    if [[ $cur == -* ]]; then'
echo "        COMPREPLY=(\$(compgen -W \"${opts[*]}\" -- \"\$cur\"))"
echo '    else'
echo '        compopt -o filenames; COMPREPLY=($(compgen -f -- "$cur"))'
echo '    fi'
echo "}"
echo "complete -F $fn $name"
