#include "classic_header.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <vector>

#include "core/limits.h"

namespace nph::io {
namespace {

// Tags and sizes from the classic format BNF (NetCDF Users Guide, "File Format Specifications").
constexpr std::uint32_t kTagDimension = 0x0A;
constexpr std::uint32_t kTagVariable = 0x0B;
constexpr std::uint32_t kTagAttribute = 0x0C;
constexpr std::uint64_t kStreamingRecords = 0xFFFFFFFFu;
/// Header lists longer than this are not a real file (NC_MAX_DIMS/VARS are 1024/8192 in practice).
constexpr std::uint64_t kMaxListElements = 1u << 20;

/// Big-endian reader over the header with a sticky failure flag.
class HeaderStream {
 public:
  HeaderStream(const std::string& path, int version) : in_(path, std::ios::binary), version_(version) {}
  bool ok() const { return ok_ && bool(in_); }

  std::uint64_t u32() { return be(4); }
  std::uint64_t u64() { return be(8); }
  /// NON_NEG: 4 bytes in CDF-1/2, 8 in CDF-5 (element counts, dimension lengths, vsize).
  std::uint64_t count() { return version_ == 5 ? u64() : u32(); }
  /// OFFSET (a variable's begin): 4 bytes in CDF-1, 8 in CDF-2/5.
  std::uint64_t offset() { return version_ == 1 ? u32() : u64(); }
  void skip(std::uint64_t bytes) {
    if (!ok_) return;
    in_.seekg(static_cast<std::streamoff>(bytes), std::ios::cur);
    ok_ = bool(in_);
  }
  /// name = nelems namestring, padded to 4 bytes.
  void skipName() {
    const std::uint64_t n = count();
    if (n > 1024) ok_ = false;  // NC_MAX_NAME is 256
    skip((n + 3) / 4 * 4);
  }
  /// An att_list: ABSENT (ZERO ZERO) or NC_ATTRIBUTE nelems [attr ...].
  void skipAttributes() {
    const std::uint64_t tag = u32();
    const std::uint64_t n = count();
    if (tag != kTagAttribute && !(tag == 0 && n == 0)) ok_ = false;
    if (n > kMaxListElements) ok_ = false;
    for (std::uint64_t a = 0; a < n && ok(); ++a) {
      skipName();
      const std::uint64_t type = u32();
      const std::uint64_t values = count();
      const auto bytes = limits::checkedProduct({values, typeBytes(type)});
      if (!bytes || *bytes > (std::uint64_t(1) << 40)) ok_ = false;
      if (ok()) skip((*bytes + 3) / 4 * 4);
    }
  }
  /// Bytes of one value of nc_type `type` (0 for an unknown type, which fails the walk).
  std::uint64_t typeBytes(std::uint64_t type) {
    switch (type) {
      case 1:
      case 2:
      case 7: return 1;  // NC_BYTE, NC_CHAR, NC_UBYTE
      case 3:
      case 8: return 2;  // NC_SHORT, NC_USHORT
      case 4:
      case 5:
      case 9: return 4;  // NC_INT, NC_FLOAT, NC_UINT
      case 6:
      case 10:
      case 11: return 8;  // NC_DOUBLE, NC_INT64, NC_UINT64
      default: ok_ = false; return 0;
    }
  }
  std::uint64_t position() { return ok() ? static_cast<std::uint64_t>(in_.tellg()) : 0; }

 private:
  std::uint64_t be(int bytes) {
    std::array<unsigned char, 8> b{};
    if (ok_) in_.read(reinterpret_cast<char*>(b.data()), bytes);
    ok_ = ok_ && bool(in_);
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | b[std::size_t(i)];
    return v;
  }
  std::ifstream in_;
  int version_;
  bool ok_ = true;
};

}  // namespace

std::optional<std::uint64_t> classicDataEnd_bytes(const std::string& path) {
  std::array<char, 4> magic{};
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe.read(magic.data(), magic.size())) return std::nullopt;
  }
  if (magic[0] != 'C' || magic[1] != 'D' || magic[2] != 'F' || (magic[3] != 1 && magic[3] != 2 && magic[3] != 5)) {
    return std::nullopt;
  }
  HeaderStream h(path, magic[3]);
  h.skip(4);
  std::uint64_t numrecs = h.count();
  if (numrecs == kStreamingRecords) numrecs = 0;

  // dim_list: the record dimension is the one of length 0.
  std::vector<std::uint64_t> dim_lengths;
  {
    const std::uint64_t tag = h.u32();
    const std::uint64_t n = h.count();
    if ((tag != kTagDimension && !(tag == 0 && n == 0)) || n > kMaxListElements) return std::nullopt;
    for (std::uint64_t d = 0; d < n && h.ok(); ++d) {
      h.skipName();
      dim_lengths.push_back(h.count());
    }
  }
  h.skipAttributes();

  struct Var {
    bool record = false;
    std::uint64_t bytes = 0;  ///< one record's (or the whole fixed variable's) data
    std::uint64_t begin = 0;
  };
  std::vector<Var> vars;
  {
    const std::uint64_t tag = h.u32();
    const std::uint64_t n = h.count();
    if ((tag != kTagVariable && !(tag == 0 && n == 0)) || n > kMaxListElements) return std::nullopt;
    for (std::uint64_t v = 0; v < n && h.ok(); ++v) {
      h.skipName();
      const std::uint64_t ndims = h.count();
      if (ndims > 1024) return std::nullopt;
      Var var;
      std::uint64_t elements = 1;
      for (std::uint64_t i = 0; i < ndims && h.ok(); ++i) {
        const std::uint64_t id = h.count();
        if (id >= dim_lengths.size()) return std::nullopt;
        if (dim_lengths[id] == 0) {
          if (i != 0) return std::nullopt;  // only the first dimension may be the record dimension
          var.record = true;
          continue;
        }
        const auto e = limits::checkedProduct({elements, dim_lengths[id]});
        if (!e) return std::nullopt;
        elements = *e;
      }
      h.skipAttributes();
      const std::uint64_t type_bytes = h.typeBytes(h.u32());
      (void)h.count();  // vsize: saturates at 2^32 - 1 for large variables, so recomputed here
      var.begin = h.offset();
      const auto bytes = limits::checkedProduct({elements, type_bytes});
      if (!bytes) return std::nullopt;
      var.bytes = *bytes;
      vars.push_back(var);
    }
  }
  if (!h.ok()) return std::nullopt;
  std::uint64_t end = h.position();

  // One record holds every record variable's slab, each padded to 4 bytes, except when there is
  // exactly one record variable (then records are packed without padding).
  const auto record_vars = std::count_if(vars.begin(), vars.end(), [](const Var& v) { return v.record; });
  std::uint64_t record_bytes = 0;
  for (const Var& v : vars) {
    if (v.record) record_bytes += record_vars == 1 ? v.bytes : (v.bytes + 3) / 4 * 4;
  }
  for (const Var& v : vars) {
    std::uint64_t var_end = 0;
    if (__builtin_add_overflow(v.begin, v.bytes, &var_end)) return std::nullopt;
    if (v.record) {
      if (numrecs == 0) continue;
      const auto before_last = limits::checkedProduct({numrecs - 1, record_bytes});
      if (!before_last || __builtin_add_overflow(var_end, *before_last, &var_end)) return std::nullopt;
    }
    end = std::max(end, var_end);
  }
  return end;
}

}  // namespace nph::io
