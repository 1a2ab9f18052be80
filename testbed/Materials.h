// The `materials` scene: physical (glTF metallic-roughness) materials to look at, +Y up like a glTF file. A row of
// spheres per metallic value (0, 0.5, 1) across roughness 0.1 to 1, a sphere with every map (base colour, normal,
// metallic-roughness, occlusion, emissive; the textures made here), a blended glass pane and a tiled floor whose
// texture is repeated through a texture transform.
#pragma once
#include "nodes/Group.h"
#include "sg/core/Mesh.h"

namespace scenes {

sg::ref_ptr<sg::Group> buildMaterials();

// A UV sphere of `radius` centred on the origin, counter-clockwise from outside: the exact sphere's normals, u
// around from +X toward -Z, v from the top (+Y), tangents from the UVs.
sg::ref_ptr<sg::Mesh> makeSphereMesh(float radius, int slices, int stacks);

}  // namespace scenes
