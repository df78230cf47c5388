#version 300 es
// llvmpipe's floor for a deferred pass (the benchmark, tools/benchmarks/bench_combine.c): read both
// G-buffer texels of the pixel and write one float, nothing else. Whatever the headlight pass
// costs above this is its own work; this much is the rasteriser, the texture fetches and the
// R32F store.
precision highp float;

uniform highp sampler2D u_pos;
uniform highp sampler2D u_nrm;

out vec4 o_out;

void main()
{
	ivec2 p = ivec2(gl_FragCoord.xy);
	o_out = vec4(texelFetch(u_pos, p, 0).w + texelFetch(u_nrm, p, 0).w, 0.0, 0.0, 1.0);
}
