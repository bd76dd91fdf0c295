# skin-plots.gp — the Fitzpatrick presets' profiles and spectra, from the tables
# dermis-fit-profile --radial / --spectrum wrote into `dir` (make gallery, scripts/gallery.sh):
#   docs/skin-profiles.png  2 pi r^2 R(r) per channel against r (log): the light leaving per
#                           ln r, so the area under a curve is the channel's total reflectance
#   docs/skin-spectra.png   the total diffuse reflectance per wavelength
#   gnuplot -e "dir='build/gallery'" scripts/skin-plots.gp
if (!exists("dir")) dir = "build/gallery"
presets = "fitzpatrick-1 fitzpatrick-2 fitzpatrick-3 fitzpatrick-4 fitzpatrick-5 fitzpatrick-6"
colours = "#f2c9a8 #dba882 #b98558 #8d5a36 #5c3a22 #2e1d12"
set datafile commentschars "#"
set datafile separator tab
set key autotitle columnhead

set terminal pngcairo size 1500,480 font "DejaVu Sans,11" background rgb "white"
set output "docs/skin-profiles.png"
set multiplot layout 1,3 title "Physical skin profiles, Fitzpatrick presets (dermis-fit-profile --radial): 2{/Symbol p}r^2 R(r), the light leaving per ln r"
set logscale x
set xrange [0.01:20]
set xlabel "r (mm)"
set grid
names = "red green blue"
do for [c=1:3] {
    set title word(names, c)." channel"
    if (c == 1) { set ylabel "2{/Symbol p} r^2 R(r)" } else { unset ylabel }
    if (c == 1) { set key top right } else { unset key }
    plot for [i=1:6] sprintf("%s/%s.radial.tsv", dir, word(presets, i)) using 1:(2*pi*$1**2*column(c+1)) \
         with lines lw 2 lc rgb word(colours, i) title word(presets, i)
}
unset multiplot

set terminal pngcairo size 800,500 font "DejaVu Sans,11" background rgb "white"
set output "docs/skin-spectra.png"
unset logscale x
set xrange [400:700]
set yrange [0:*]
set xlabel "wavelength (nm)"
set ylabel "total diffuse reflectance"
set title "Physical skin, Fitzpatrick presets: total diffuse reflectance (dermis-fit-profile --spectrum)"
set key top left
plot for [i=1:6] sprintf("%s/%s.spectrum.tsv", dir, word(presets, i)) using 1:2 with linespoints lw 2 pt 7 ps 0.6 \
     lc rgb word(colours, i) title word(presets, i)
