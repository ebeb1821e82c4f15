#version 450 core
// The reference frame's workload (reference_frame.vert): MESH lights the heightfield; otherwise a
// full-screen pass reads TAPS texels of the previous pass's image around its pixel, as a blur or a
// lighting pass reads the G-buffer.
in vec3 vNormal;
layout(binding = 0) uniform sampler2D uPrevious;
layout(location = 0) out vec4 fColour;
void main() {
#ifdef MESH
  fColour = vec4(vec3(0.2, 0.5, 0.2) * max(dot(vNormal, normalize(vec3(0.3, 0.4, 0.8))), 0.1), 1.0);
#else
  ivec2 p = ivec2(gl_FragCoord.xy), size = textureSize(uPrevious, 0) - 1;
  vec4 sum = vec4(0.0);
  for (int i = 0; i < TAPS; ++i) sum += texelFetch(uPrevious, clamp(p + ivec2(i % 4 - 2, i / 4 - 2), ivec2(0), size), 0);
  fColour = sum / float(TAPS);
#endif
}
