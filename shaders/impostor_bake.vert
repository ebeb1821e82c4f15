#version 450 core
// Impostor bake (render/src/impostor_atlas.cpp): a species' LOD0 in object space seen by one bake
// view's orthographic camera (vegetation/impostor_views.hpp). clip = (p − c)·right / R,
// (p − c)·up / R, and depth s / 2R with s = R − (p − c)·toViewer, the distance from the plane that
// touches the bake sphere on the viewer's side (0 … 2R; the clip control maps z to [0, 1]).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aAlbedo;

uniform vec4 uCentreRadius;  // the bake sphere: centre (object space), radius R
uniform vec3 uRight, uUp, uToViewer;

out vec3 vNormal;
out vec3 vAlbedo;

void main() {
  vec3 q = aPosition - uCentreRadius.xyz;
  float r = uCentreRadius.w;
  vNormal = aNormal;
  vAlbedo = aAlbedo;
  gl_Position = vec4(dot(q, uRight) / r, dot(q, uUp) / r, (r - dot(q, uToViewer)) / (2.0 * r), 1.0);
}
