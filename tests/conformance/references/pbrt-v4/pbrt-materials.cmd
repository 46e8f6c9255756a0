# pbrt-v4 (commit 5f7a606806a4ac7b939131ded9d7a30ebd02416e, CPU, built by tools/conformance/build-pbrt.sh), run in tests/conformance/, 80 s
pbrt --nthreads 2 --seed 0 --spp 8192 --outfile references/pbrt-v4/pbrt-materials.pfm scenes/pbrt-materials.pbrt
