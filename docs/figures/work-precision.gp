# work-precision.gp: run  gnuplot work-precision.gp  in this folder to redraw work-precision.png;
# gnuplot -e "out='other.svg'" work-precision.gp draws elsewhere (.png or .svg).
if (!exists("out")) out = 'work-precision.png'
if (!exists("fmt")) fmt = out[strlen(out)-2:]
stem = 'work-precision'
set encoding utf8
if (fmt eq 'svg') {
  set terminal svg size 1280,1240 dynamic enhanced font 'DejaVu Sans,13' background rgb 'white'
} else {
  set terminal pngcairo size 1629,1578 enhanced font 'DejaVu Sans,13' background rgb 'white'
}
set output out
set datafile separator ','
set grid lc rgb '#dddddd'
set datafile separator ','
set logscale xy
set format y '10^{%L}'
set format x '10^{%L}'
set key outside bottom center horizontal maxrows 5 font ',9' noenhanced
set xlabel 'CPU time per period [us]'
set ylabel 'final error'
colors = '#1f77b4 #d62728 #2ca02c #ff7f0e #9467bd #8c564b #e377c2 #7f7f7f #bcbd22 #17becf #000000 #393b79 #637939 #8c6d31 #843c39 #7b4173 #5254a3 #8ca252 #bd9e39 #ad494a #a55194 #e6550d #31a354 #756bb1'
set multiplot layout 2,2
set title 'pendulum' font ',14'
names = 'newmark simpson lobatto-3 lobatto-4 lobatto-5 lobatto-6 gauss-2 gauss-3 gauss-4 gauss-5 gauss-6 yoshida-6 yoshida-6-kdk kahan-li-8 kahan-li-8-kdk odeint-velocity_verlet odeint-sb3a_mclachlan odeint-sb3a_m4_mclachlan'
plot for [i=0:17] stem.'-pendulum.csv' index i using 1:2 with linespoints lw 2 lc rgb word(colors, (i % 24) + 1) pt ((i % 13) + 1) ps 1.2 title (word(names, i + 1))
set title 'pendulum-2.5' font ',14'
names = 'newmark simpson lobatto-3 lobatto-4 lobatto-5 lobatto-6 gauss-2 gauss-3 gauss-4 gauss-5 gauss-6 yoshida-6 yoshida-6-kdk kahan-li-8 kahan-li-8-kdk odeint-velocity_verlet odeint-sb3a_mclachlan odeint-sb3a_m4_mclachlan'
plot for [i=0:17] stem.'-pendulum-2.5.csv' index i using 1:2 with linespoints lw 2 lc rgb word(colors, (i % 24) + 1) pt ((i % 13) + 1) ps 1.2 title (word(names, i + 1))
set title 'kepler' font ',14'
names = 'newmark simpson lobatto-3 lobatto-4 lobatto-5 lobatto-6 gauss-2 gauss-3 gauss-4 gauss-5 gauss-6 yoshida-6 yoshida-6-kdk kahan-li-8 kahan-li-8-kdk odeint-velocity_verlet odeint-sb3a_mclachlan odeint-sb3a_m4_mclachlan'
plot for [i=0:17] stem.'-kepler.csv' index i using 1:2 with linespoints lw 2 lc rgb word(colors, (i % 24) + 1) pt ((i % 13) + 1) ps 1.2 title (word(names, i + 1))
set title 'solar' font ',14'
names = 'newmark simpson lobatto-3 lobatto-4 lobatto-5 lobatto-6 gauss-2 gauss-3 gauss-4 gauss-5 gauss-6 yoshida-6 yoshida-6-kdk kahan-li-8 kahan-li-8-kdk odeint-velocity_verlet odeint-sb3a_mclachlan odeint-sb3a_m4_mclachlan'
plot for [i=0:17] stem.'-solar.csv' index i using 1:2 with linespoints lw 2 lc rgb word(colors, (i % 24) + 1) pt ((i % 13) + 1) ps 1.2 title (word(names, i + 1))
unset multiplot
