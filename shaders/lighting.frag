#version 450 core
// Lighting (thesis §6.2): Phong — Lambert diffuse and a weak Blinn-Phong highlight from the sun,
// both times the shadow term — plus a weak global ambient; the sky colour where nothing was drawn.
in vec2 vUv;

uniform sampler2D uAlbedo;
uniform sampler2D uShadingNormal;
uniform sampler2D uDepth;
uniform usampler2D uObjectId;
uniform sampler2D uShadowTerm;
uniform mat4 uInverseViewProjectionRelative;
uniform vec3 uToSun;
uniform vec3 uSunColor;
uniform float uAmbient;
uniform vec3 uSky;
uniform bool uSunUp;
uniform float uFogDensity;   // per metre; 0: no fog (exponential fog toward the sky colour)

out vec4 fragColor;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  if (texelFetch(uObjectId, pixel, 0).r == 0u) { fragColor = vec4(uSky, 1.0); return; }
  vec3 albedo = texelFetch(uAlbedo, pixel, 0).rgb;
  vec3 n = normalize(texelFetch(uShadingNormal, pixel, 0).xyz);
  float shadow = texelFetch(uShadowTerm, pixel, 0).r;
  vec3 linear = albedo * uAmbient;
  vec4 h = uInverseViewProjectionRelative * vec4(2.0 * vUv - 1.0, texelFetch(uDepth, pixel, 0).r, 1.0);
  vec3 relative = h.xyz / h.w;
  if (uSunUp) {
    vec3 toEye = normalize(-relative);
    float diffuse = max(dot(n, uToSun), 0.0);
    float specular = pow(max(dot(n, normalize(uToSun + toEye)), 0.0), 32.0) * step(0.0, dot(n, uToSun));
    linear += (1.0 - uAmbient) * shadow * uSunColor * (albedo * diffuse + 0.04 * specular);
  }
  vec3 display = pow(linear, vec3(1.0 / 2.2));
  fragColor = vec4(mix(uSky, display, exp(-uFogDensity * length(relative))), 1.0);
}
