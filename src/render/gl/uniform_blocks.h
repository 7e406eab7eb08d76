#pragma once
// std140 uniform blocks shared by several passes, each declared once as a C++ struct with
// static_asserts on size and offsets (STYLE.md 4, after Filament's UibStructs.h; issue #17 item 4).
//
// std140 rules used here (GL 4.5 core spec §7.6.2.2): a float/int/bool takes 4 bytes aligned to 4
// (a bool is stored as a 32-bit word, non-zero = true); a vec2/ivec2 8 bytes aligned to 8; a
// vec3/ivec3 12 bytes aligned to 16, so a scalar may fill the fourth word after it; the block size
// is rounded up to 16. Each struct below mirrors its GLSL block member for member: the GLSL name
// of every member and its offset are listed in kMembers, and the GL test
// UniformBlocks.MatchTheLinkedPrograms checks each one against the driver's layout
// (GL_OFFSET, GL_BUFFER_DATA_SIZE) of every program that uses the block — a member added, moved
// or retyped on one side only fails there, not as a silently wrong picture.
//
// The blocks replace the groups of plain uniforms that several programs share (light space,
// volume): a program that does not read every member of a group has no inactive uniform to trip
// the strict-uniform check (program.h), and a group is uploaded once per change, not per program.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <glm/glm.hpp>

#include "render/gl/bindings.h"
#include "render/gl/objects.h"

namespace nph::gl {

/// One member of a uniform block: its GLSL name and its std140 byte offset in the C++ struct.
struct BlockMember {
  const char* glsl_name;
  std::size_t offset;
};

/// glsl/dlm/light_space.glsl `LightSpaceBlock`: the deep light map's light space
/// (scene/light_space.h), read by the DLM passes, the look-up and the ray caster.
struct LightSpaceBlock {
  static constexpr unsigned kBinding = binding::UBO_LIGHT_SPACE;
  static constexpr const char* kGlslName = "LightSpaceBlock";
  glm::vec3 origin_m{0.0f};  ///< u_ls_origin_m: world position of light-space (0, 0, 0)
  float depth_m = 0.0f;      ///< u_ls_depth_m: length of every light ray
  glm::vec3 u{0.0f};         ///< u_ls_u
  float pad_u = 0.0f;
  glm::vec3 v{0.0f};         ///< u_ls_v
  float pad_v = 0.0f;
  glm::vec3 w{0.0f};         ///< u_ls_w: the direction the sunlight travels
  float pad_w = 0.0f;
  glm::vec2 texel_m{0.0f};   ///< u_ls_texel_m: du, dv
  glm::ivec2 texels{0};      ///< u_ls_texels: nu, nv
};
static_assert(offsetof(LightSpaceBlock, origin_m) == 0 && offsetof(LightSpaceBlock, depth_m) == 12);
static_assert(offsetof(LightSpaceBlock, u) == 16 && offsetof(LightSpaceBlock, v) == 32 &&
              offsetof(LightSpaceBlock, w) == 48);
static_assert(offsetof(LightSpaceBlock, texel_m) == 64 && offsetof(LightSpaceBlock, texels) == 72);
static_assert(sizeof(LightSpaceBlock) == 80, "std140 size of LightSpaceBlock");
inline constexpr BlockMember kLightSpaceMembers[] = {
    {"u_ls_origin_m", offsetof(LightSpaceBlock, origin_m)}, {"u_ls_depth_m", offsetof(LightSpaceBlock, depth_m)},
    {"u_ls_u", offsetof(LightSpaceBlock, u)},               {"u_ls_v", offsetof(LightSpaceBlock, v)},
    {"u_ls_w", offsetof(LightSpaceBlock, w)},               {"u_ls_texel_m", offsetof(LightSpaceBlock, texel_m)},
    {"u_ls_texels", offsetof(LightSpaceBlock, texels)}};

/// glsl/dlm/volume.glsl `VolumeBlock`: where the extinction volumes sit and what they hold
/// (render/dlm/volume_textures.h), read by every pass that samples them.
struct VolumeBlock {
  static constexpr unsigned kBinding = binding::UBO_VOLUME;
  static constexpr const char* kGlslName = "VolumeBlock";
  glm::vec3 box_min_m{0.0f};   ///< u_box_min_m: world AABB of the volume
  std::int32_t brick_voxels = 0;  ///< u_brick_voxels: occupancy brick side [voxels]
  glm::vec3 box_size_m{0.0f};  ///< u_box_size_m
  std::uint32_t has_ice = 0;   ///< u_has_ice (bool): absent phases are never fetched
  glm::ivec3 voxels{0};        ///< u_voxels
  std::uint32_t has_water = 0; ///< u_has_water (bool)
};
static_assert(offsetof(VolumeBlock, box_min_m) == 0 && offsetof(VolumeBlock, brick_voxels) == 12);
static_assert(offsetof(VolumeBlock, box_size_m) == 16 && offsetof(VolumeBlock, has_ice) == 28);
static_assert(offsetof(VolumeBlock, voxels) == 32 && offsetof(VolumeBlock, has_water) == 44);
static_assert(sizeof(VolumeBlock) == 48, "std140 size of VolumeBlock");
inline constexpr BlockMember kVolumeMembers[] = {
    {"u_box_min_m", offsetof(VolumeBlock, box_min_m)}, {"u_brick_voxels", offsetof(VolumeBlock, brick_voxels)},
    {"u_box_size_m", offsetof(VolumeBlock, box_size_m)}, {"u_has_ice", offsetof(VolumeBlock, has_ice)},
    {"u_voxels", offsetof(VolumeBlock, voxels)},         {"u_has_water", offsetof(VolumeBlock, has_water)}};

/// A uniform buffer holding one `Block`, bound to the block's binding point (bindings.h).
template <class Block>
class UniformBuffer {
 public:
  UniformBuffer() = default;
  static UniformBuffer create(const Block& contents, std::string_view label) {
    UniformBuffer b;
    b.buffer_ = Buffer::create(sizeof(Block), &contents).label(label);
    return b;
  }
  void update(const Block& contents) { buffer_.upload(0, sizeof(Block), &contents); }
  /// glBindBufferBase(GL_UNIFORM_BUFFER, Block::kBinding, ...): every program that declares the
  /// block reads this buffer until something else is bound there.
  void bind() const { glBindBufferBase(GL_UNIFORM_BUFFER, Block::kBinding, buffer_.id()); }
  explicit operator bool() const { return bool(buffer_.id()); }

 private:
  Buffer buffer_;
};

}  // namespace nph::gl
