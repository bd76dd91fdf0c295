#!/usr/bin/env bash
# help-options.sh TOOL — the options a dermis tool's --help documents, one per line:
#   OPTION<TAB>VALUE
# VALUE is the placeholder printed after the option where it takes one (FILE, N, WxH,
# sphere|quad, ...), empty for a flag. The one reading of --help that the bash completion
# (scripts/gen-completion.sh) and the man-page check (scripts/test-install.sh) share, so
# neither can drift from what the tool prints.
#
# What counts as an option: a "--name" anywhere in the text; a "-x" (one letter) only where
# options are defined — at the start of an indented option line, after "-x, ", or in the
# Usage lines (so "looking along -Z" in prose is not one). VALUE comes from the option's
# first definition line ("  --size N   text": N) or, failing that, from its first mention
# followed by a word in capitals ("--thickness MM") or a list of values ("--synthetic
# sphere|quad", which is preferred to a placeholder).
set -euo pipefail
tool=${1:?usage: help-options.sh TOOL}
"$tool" --help 2>&1 | awk '
  # def: the placeholder on the option'"'"'s definition line (wins); prose: elsewhere
  function note(opt, val, def) {
    if (!(opt in seen)) { seen[opt] = 1; order[++n] = opt }
    sub(/[.,]+$/, "", val)
    if (val == "") return
    if (def && !(opt in dval)) dval[opt] = val
    if (!def && !(opt in pval)) pval[opt] = val
  }
  NR == 1 || /^ *(Usage|or):/ { usage = 1 }
  /^ *$/ { usage = 0 }
  {
    line = $0
    # short options: at the start of an option line ("  -o FILE", "  -v, --verbose"), or in
    # the Usage lines ("[-v | --quiet]", "-o OUT.exr")
    if (match(line, /^ +-[A-Za-z]([ ,]|$)/)) {
      tok = substr(line, RSTART, RLENGTH); gsub(/[ ,]/, "", tok)
      val = ""
      if (match(line, /^ +-[A-Za-z] [^ -][^ ]*/)) { val = substr(line, RSTART, RLENGTH); sub(/^ +-[A-Za-z] /, "", val) }
      # "-o, --output FILE": the short form takes what the long one takes
      else if (match(line, /^ +-[A-Za-z], --[A-Za-z0-9-]+ [^ -][^ ]*/)) { val = substr(line, RSTART, RLENGTH); sub(/^.* /, "", val) }
      note(tok, val, 1)
    }
    if (usage) {
      s = line
      while (match(s, /(^|[ [(|])-[A-Za-z]([ \]|)]|$)/)) {
        tok = substr(s, RSTART, RLENGTH); sub(/^[ [(|]/, "", tok); sub(/[ \]|)]$/, "", tok)
        rest = substr(s, RSTART + RLENGTH - 1)
        w = ""
        if (rest ~ /^ [A-Z]/) { w = substr(rest, 2); sub(/[ \])|].*$/, "", w) }
        note(tok, w, 0)
        s = substr(s, RSTART + 2)
      }
    }
    # long options, anywhere
    s = line; defline = (line ~ /^ +(-[A-Za-z], )?--[A-Za-z0-9]/)
    while (match(s, /(^|[^A-Za-z0-9-])--[A-Za-z0-9][A-Za-z0-9-]*/)) {
      tok = substr(s, RSTART, RLENGTH); sub(/^[^-]/, "", tok)
      rest = substr(s, RSTART + RLENGTH)
      val = ""
      if (rest ~ /^ [^ -]/) {
        w = substr(rest, 2); sub(/[ \])].*$/, "", w); sub(/[,;.]$/, "", w)
        # the first option of a definition line takes any word as its placeholder
        # ("--preset gems3-skin   text"); elsewhere only a word in capitals ("--thickness MM")
        if (defline || w ~ /^[A-Z][A-Za-z0-9.,|\/_x-]*$/ || w ~ /^[a-z0-9-]+(\|[a-z0-9-]+)+$/) val = w
      }
      note(tok, val, defline)
      defline = 0
      s = rest
    }
  }
  END {
    for (i = 1; i <= n; ++i) {
      o = order[i]
      # a list of the values themselves (sphere|quad) says more than a placeholder (SHAPE)
      if ((o in pval) && pval[o] ~ /^[a-z0-9-]+(\|[a-z0-9-]+)+$/) dval[o] = pval[o]
      printf "%s\t%s\n", o, (o in dval) ? dval[o] : (o in pval) ? pval[o] : ""
    }
  }
'
