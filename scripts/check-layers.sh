#!/usr/bin/env bash
# check-layers.sh — the house rules of docs/architecture.md, checked (make test runs it).
#
#   scripts/check-layers.sh [--root DIR] [--build DIR]
#
# Rooms, bottom to top: core pack image mesh bake reference packer render host, and inside
# render: gpu input picture frame passes, then render's own top-level files. It fails, naming
# the file, the line and the rule, when:
#   order     a file under lib/ includes a header from a room above its own;
#   runtime   a runtime room (core, pack, render, host) includes an offline room's header
#             (image, mesh, bake, reference, packer) or an offline third-party header
#             (OpenEXR, OpenImageIO, OpenMesh, Embree, tinygltf);
#   render    a render room includes a render room above it (gpu: only core and gpu, never
#             the renderer, the scene or the plan); the render/ top-level headers are the
#             public API every render room but gpu may name;
#   passes    a file in render/passes/ includes another pass's header (its own is the one
#             whose name starts its file name: dm_pass_tsd.h for dm_pass_tsd_blur.c);
#   mutual    two files of lib/ or tools/ each include the other's header (each calls the other);
#   link      with --build, a runtime library (libdermis_core.a, libdermis_render.a,
#             libdermis_host_osmesa.a) needs a symbol the offline library (libdermis_bake.a)
#             or an offline third-party library defines, or a runtime tool (dermis-render,
#             dermis-view) loads an offline third-party library.
# There is no exception list. Exit 0 when every rule holds, 1 otherwise, 2 for bad usage.
set -u
root=.
build=
while [ $# -gt 0 ]; do
    case $1 in
    --root) root=${2:?--root needs a folder}; shift 2 ;;
    --build) build=${2:?--build needs a folder}; shift 2 ;;
    -h | --help) sed -n '2,/^set -u/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "check-layers.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done
[ -d "$root/lib" ] || { echo "check-layers.sh: no lib/ folder under '$root'" >&2; exit 2; }
cd "$root" || exit 2

ROOMS=(core pack image mesh bake reference packer render host)
RUNTIME=" core pack render host "
RENDER_ROOMS=(gpu input picture frame passes)
OFFLINE_3P='OpenEXR/|openexr\.h|OpenImageIO/|OpenMesh/|embree[0-9]*/|tiny_gltf\.h'
failures=0
fail() { # file line rule message
    printf '%s:%s: [%s] %s\n' "$1" "$2" "$3" "$4"
    failures=$((failures + 1))
}
rank() { # room -> index in ROOMS, or -1
    local i
    for i in "${!ROOMS[@]}"; do [ "${ROOMS[$i]}" = "$1" ] && { echo "$i"; return; }; done
    echo -1
}
render_rank() { # path under lib/render -> 0..4 for the sub-rooms, 5 for top-level files
    local sub=${1#lib/render/} i
    case $sub in */*) ;; *) echo 5; return ;; esac
    for i in "${!RENDER_ROOMS[@]}"; do [ "${sub%%/*}" = "${RENDER_ROOMS[$i]}" ] && { echo "$i"; return; }; done
    echo 5
}

# Every quoted include of every C/C++ file under lib/ and tools/: FILE LINE HEADER.
includes=$(grep -rnE --include='*.c' --include='*.h' --include='*.cpp' '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]' lib tools 2>/dev/null |
    sed -E 's/^([^:]*):([0-9]*):[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]([^>"]*)[>"].*/\1 \2 \3/')

while read -r file line hdr; do
    [ -n "$file" ] || continue
    case $file in lib/*) ;; *) continue ;; esac
    room=${file#lib/}; room=${room%%/*}
    hroom=${hdr%%/*}
    rr=$(rank "$room")
    if [[ $RUNTIME == *" $room "* ]] && [[ $hdr =~ ^($OFFLINE_3P) ]]; then
        fail "$file" "$line" runtime "the runtime room '$room' includes the offline library header <$hdr>"
    fi
    [ "$hdr" != "$hroom" ] || continue # a bare system header
    hr=$(rank "$hroom")
    [ "$hr" -ge 0 ] || continue        # not one of ours (GL/, cjson/...)
    if [[ $RUNTIME == *" $room "* ]] && [[ $RUNTIME != *" $hroom "* ]]; then
        fail "$file" "$line" runtime "the runtime room '$room' includes '$hdr' from the offline room '$hroom'"
    elif [ "$hr" -gt "$rr" ]; then
        fail "$file" "$line" order "'$room' includes '$hdr' from '$hroom', a room above it"
    fi
    if [ "$room" = render ] && [ "$hroom" = render ]; then
        fr=$(render_rank "$file")
        case ${hdr#render/} in
        */*) hrr=$(render_rank "lib/$hdr") ;;
        *) hrr=-1; [ "$fr" -eq 0 ] && hrr=5 ;; # the public API: above gpu only
        esac
        if [ "$hrr" -gt "$fr" ]; then
            fail "$file" "$line" render "render/${RENDER_ROOMS[$fr]:-top} includes '$hdr', a render room above it"
        fi
        if [ "$fr" -eq 4 ] && [ "$hrr" -eq 4 ]; then
            own=$(basename "$hdr" .h)
            stem=$(basename "$file"); stem=${stem%.*}
            [[ $stem == "$own"* ]] || fail "$file" "$line" passes "a pass includes another pass's header '$hdr'"
        fi
    fi
    if [ "$room" = render ] && [ "$(render_rank "$file")" -eq 0 ] && [[ $hdr == core/dm_scene* ]]; then
        fail "$file" "$line" render "render/gpu includes the scene '$hdr'"
    fi
done <<<"$includes"

# mutual: A.c includes B.h and B.c includes A.h (same folder or not).
pairs=$(while read -r file line hdr; do
    case $file in *.c | *.cpp) ;; *) continue ;; esac
    case $hdr in */*) ;; *) hdr=$(dirname "${file#lib/}")/$hdr ;; esac
    src=${file#lib/}; src=${src%.*}
    own=${hdr%.h}
    [ "$own" != "$src" ] && [ -n "$own" ] && echo "$src $own $file $line"
done <<<"$includes" | sort -u)
declare -A edge=()
while read -r a b file line; do [ -n "$a" ] && edge["$a>$b"]="$file:$line"; done <<<"$pairs"
for k in "${!edge[@]}"; do
    a=${k%%>*}; b=${k#*>}
    if [[ -n ${edge["$b>$a"]+x} ]] && [[ $a < $b ]]; then
        fail "${edge[$k]%%:*}" "${edge[$k]##*:}" mutual "'$a' and '$b' include each other's header (${edge["$b>$a"]})"
    fi
done

# link: what the built runtime libraries and tools need.
if [ -n "$build" ]; then
    lib=$build/lib
    if [ ! -f "$lib/libdermis_core.a" ] || [ ! -f "$lib/libdermis_bake.a" ]; then
        echo "check-layers.sh: no built libraries in '$lib' (make first)" >&2; exit 2
    fi
    offline=$(nm --defined-only -g "$lib/libdermis_bake.a" 2>/dev/null | awk 'NF == 3 {print $3}' | sort -u)
    for a in libdermis_core.a libdermis_render.a libdermis_host_osmesa.a; do
        [ -f "$lib/$a" ] || continue
        need=$(nm -u "$lib/$a" 2>/dev/null | awk '{print $NF}' | sort -u)
        bad=$(comm -12 <(echo "$need") <(echo "$offline") | head -5)
        [ -z "$bad" ] || fail "$lib/$a" 0 link "needs the offline library's $(echo $bad | tr ' ' ',')"
        bad=$(echo "$need" | grep -E '^(exr_|Imf|_ZN.*OpenImageIO|_ZN.*OpenMesh|rtc[A-Z]|_ZN.*tinygltf)' | head -3)
        [ -z "$bad" ] || fail "$lib/$a" 0 link "needs an offline third-party library: $(echo $bad | tr ' ' ',')"
    done
    # mutual, by symbol: two objects of a library or of the viewer each call the other.
    view_obj=$(ls "$build"/obj/tools/view/*.o 2>/dev/null)
    while read -r a b why; do
        [ -n "$a" ] && fail "$a" 0 mutual "'$a' and '$b' call each other ($why)"
    done < <(nm -A "$lib"/libdermis_*.a $view_obj 2>/dev/null | awk '
        { n = split($1, p, ":"); obj = p[n - 1]; sub(/.*\//, "", obj); sym = $NF; t = (NF == 3) ? $2 : $1
          if (t == "U") U[c++] = obj " " sym; else if (t ~ /^[TDBRCVW]$/) def[sym] = obj }
        END { for (i = 0; i < c; i++) { split(U[i], a, " ")
                  if ((a[2] in def) && def[a[2]] != a[1]) e[a[1] " " def[a[2]]] = a[2] }
              for (k in e) { split(k, b, " "); r = b[2] " " b[1]
                  if ((r in e) && b[1] < b[2]) print b[1], b[2], b[1] " uses " e[k] ", " b[2] " uses " e[r] } }' | sort)
    for t in dermis-render dermis-view; do
        [ -x "$build/bin/$t" ] || continue
        bad=$(readelf -d "$build/bin/$t" 2>/dev/null | grep -oE 'lib(OpenEXR|OpenImageIO|OpenMesh|embree|Imath|Iex)[^]]*' | head -3)
        [ -z "$bad" ] || fail "$build/bin/$t" 0 link "the runtime tool loads $(echo $bad | tr ' ' ',')"
    done
fi

if [ "$failures" -gt 0 ]; then
    echo "check-layers.sh: $failures rule(s) broken (docs/architecture.md lists the rules)" >&2
    exit 1
fi
echo "check-layers.sh: every layer rule holds ($(echo "$includes" | wc -l) includes${build:+, libraries and runtime tools in $build})"
