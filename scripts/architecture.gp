# architecture.gp — draws docs/architecture.png, the rooms of lib/ and the includes allowed
# between them (docs/architecture.md; scripts/check-layers.sh checks them).
#   gnuplot scripts/architecture.gp
set terminal pngcairo size 1100,820 font "DejaVu Sans,12" background rgb "white"
set output "docs/architecture.png"
unset border; unset tics; unset key
set xrange [0:110]; set yrange [-5:82]
set style fill solid 1.0 border lc rgb "#404040"


rt = "#dbe9f6"; of = "#f6e3cf"; tl = "#e4f2dc"; rd = "#c4dbf0"
set object 1 rect from 2,2 to 52,12 fc rgb rt                      # core
set label 1 "lib/core\nerrors, math, BRDF, profiles, scene,\nJSON, provenance, files, threads" at 27,7 center
set object 2 rect from 2,15 to 52,22 fc rgb rt                     # pack
set label 2 "lib/pack  the .dpk: format, reader, verifier, writer" at 27,18.5 center
set object 3 rect from 58,2 to 108,9 fc rgb of                     # image
set label 3 "lib/image  OpenEXR, OpenImageIO" at 83,5.5 center
set object 4 rect from 58,12 to 108,19 fc rgb of                   # mesh
set label 4 "lib/mesh  OpenMesh, tinygltf (isolated),\nchecks, UV raster, gutters, Embree rays" at 83,15.5 center
set object 5 rect from 58,22 to 108,29 fc rgb of                   # bake
set label 5 "lib/bake  LUTs, stretch, curvature, seams,\nthin parts, profile fits, environment" at 83,25.5 center
set object 6 rect from 58,32 to 108,39 fc rgb of                   # reference
set label 6 "lib/reference  the ground truth" at 83,35.5 center
set object 7 rect from 58,42 to 108,49 fc rgb of                   # packer
set label 7 "lib/packer  scene → .dpk, the step table" at 83,45.5 center
set object 8 rect from 2,25 to 52,62 fc rgb "#eef5fb"              # render frame
set label 8 "lib/render" at 4,60 left font "DejaVu Sans Bold,12"
set object 9 rect from 4,27 to 17,37 fc rgb rd
set label 9 "gpu/\nGL only" at 10.5,32 center
set object 10 rect from 20,27 to 34,37 fc rgb rd
set label 10 "input/\nno GL: pack,\nsynthetic, plan" at 27,32 center font "DejaVu Sans,10"
set object 11 rect from 37,27 to 50,37 fc rgb rd
set label 11 "picture/\nno GL: font,\nimages, compare" at 43.5,32 center font "DejaVu Sans,10"
set object 12 rect from 4,40 to 50,46 fc rgb rd
set label 12 "frame/  frame context, units, defines, one binder" at 27,43 center
set object 13 rect from 4,49 to 50,54 fc rgb rd
set label 13 "passes/  one file a pass; passes never call passes" at 27,51.5 center
set object 14 rect from 17,55.5 to 50,59 fc rgb rd
set label 14 "dm\\_render*.c  pass table, frame loop" at 33.5,57.2 center font "DejaVu Sans,11"
set object 15 rect from 2,65 to 52,71 fc rgb rt
set label 15 "lib/host  OSMesa context" at 27,68 center
set object 16 rect from 2,74 to 108,80 fc rgb tl
set label 16 "tools/  one small C file per executable; tools/view/ the viewer  (and tests/, bench/, fuzz/, examples/)" at 55,77 center
set label 20 "runtime (libdermis\\_core, libdermis\\_render, libdermis\\_host\\_osmesa):\ncJSON, xxHash, zlib and the caller's GL only" at 2,-2 left font "DejaVu Sans,10" tc rgb "#305070"
set label 21 "offline (libdermis\\_bake): OpenEXR, OpenImageIO, OpenMesh,\ntinygltf, Embree" at 58,-2 left font "DejaVu Sans,10" tc rgb "#805020"
set style arrow 1 head filled size 1.2,20 lw 1.6 lc rgb "#303030"
set style arrow 2 head filled size 1.2,20 lw 1.6 lc rgb "#b03030" dt 2
# allowed includes: downward
set arrow from 27,15 to 27,12 as 1
set arrow from 27,27 to 27,22 as 1
set arrow from 27,40 to 27,37 as 1
set arrow from 10.5,40 to 10.5,37 as 1
set arrow from 43.5,40 to 43.5,37 as 1
set arrow from 27,49 to 27,46 as 1
set arrow from 33.5,55.5 to 33.5,54 as 1
set arrow from 27,65 to 27,62 as 1
set arrow from 83,12 to 83,9 as 1
set arrow from 83,22 to 83,19 as 1
set arrow from 83,32 to 83,29 as 1
set arrow from 83,42 to 83,39 as 1
set arrow from 58,5.5 to 52,7 as 1
set arrow from 58,15.5 to 52,18.5 as 1
set arrow from 55,74 to 55,49 as 1
set arrow from 27,74 to 27,71 as 1
# forbidden: runtime to offline
set arrow from 50,34 to 58,34 as 2
set label 22 "never" at 54,35.5 center font "DejaVu Sans,10" tc rgb "#b03030"
plot NaN
