#include "render/dlm/volume_textures.h"

#include "core/error.h"

namespace nph::render {

namespace {
gl::Texture upload3D(const std::vector<float>& data, glm::ivec3 size, const char* label) {
  auto t = gl::Texture::create3D(GL_R32F, size.x, size.y, size.z).label(label);
  glTextureSubImage3D(t.id(), 0, 0, 0, 0, size.x, size.y, size.z, GL_RED, GL_FLOAT, data.data());
  return t;
}
bool anyPositive(const std::vector<float>& a) {
  for (float x : a)
    if (x > 0.0f) return true;
  return false;
}
}  // namespace

VolumeTextures VolumeTextures::upload(const ExtinctionVolumes& v, const scene::VolumeFrame& frame,
                                      std::string identity, int brickVoxels) {
  if (v.voxelCount() == 0) throw UsageError("VolumeTextures::upload: empty volume");
  VolumeTextures t;
  t.frame_ = frame;
  t.identity_ = std::move(identity);
  t.occupancy_ = scene::buildOccupancy(v, brickVoxels);
  const glm::ivec3 n(v.nx, v.ny, v.nz);
  if (v.ice_per_m.size() == v.voxelCount() && anyPositive(v.ice_per_m)) {
    t.ice_ = upload3D(v.ice_per_m, n, "ice extinction [1/m]");
    t.ice_.sampling(GL_LINEAR, GL_CLAMP_TO_BORDER);
  }
  if (v.water_per_m.size() == v.voxelCount() && anyPositive(v.water_per_m)) {
    t.water_ = upload3D(v.water_per_m, n, "water extinction [1/m]");
    t.water_.sampling(GL_LINEAR, GL_CLAMP_TO_BORDER);
  }
  t.occupancy_tex_ = upload3D(t.occupancy_.max_per_m, t.occupancy_.bricks, "occupancy max [1/m]");
  t.occupancy_tex_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
  // Units of absent phases get a 1-voxel zero texture so that no unit is left unbound.
  t.zero_ = upload3D(std::vector<float>{0.0f}, {1, 1, 1}, "zero");
  return t;
}

void VolumeTextures::nonEmptyBox(glm::dvec3& lo, glm::dvec3& hi) const {
  if (occupancy_.empty()) {
    lo = frame_.min_m();
    hi = glm::dvec3(frame_.max_m().x, frame_.max_m().y, frame_.min_m().z);
    return;
  }
  // Trilinear reach: β is non-zero up to one voxel centre-distance past a non-zero voxel,
  // including the fading shell outside the box (glsl/dlm/volume.glsl).
  const glm::dvec3 a = glm::dvec3(occupancy_.nonEmptyMinVoxel - 1);
  const glm::dvec3 b = glm::dvec3(occupancy_.nonEmptyMaxVoxel + 2);
  lo = frame_.worldFromGrid(a);
  hi = frame_.worldFromGrid(b);
}

void VolumeTextures::bind(const gl::Program& p) const {
  glBindTextureUnit(0, ice_ ? ice_.id() : zero_.id());
  glBindTextureUnit(1, water_ ? water_.id() : zero_.id());
  glBindTextureUnit(2, occupancy_tex_.id());
  p.set("u_box_min_m", glm::vec3(frame_.min_m()));
  p.set("u_box_size_m", glm::vec3(frame_.size_m()));
  p.set("u_voxels", frame_.voxels);
  p.set("u_brick_voxels", occupancy_.brick);
  p.set("u_has_ice", hasIce() ? 1 : 0);
  p.set("u_has_water", hasWater() ? 1 : 0);
}

}  // namespace nph::render
