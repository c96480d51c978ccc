#include "rayscope/accel/leaf_records.h"

namespace rayscope {

LeafRecords::LeafRecords(std::vector<PrimRecord> held) {
  std::call_once(once_, [&] {
    records_ = std::make_shared<const std::vector<PrimRecord>>(std::move(held));
    held_ = true;
  });
}

LeafRecords::LeafRecords(const LeafRecords& other, Make make) : make_(std::move(make)) {
  if (other.held())
    std::call_once(once_, [&] {
      records_ = other.records_;
      held_ = true;
    });
}

const std::vector<PrimRecord>& LeafRecords::make() const {
  std::call_once(once_, [this] {
    records_ = std::make_shared<const std::vector<PrimRecord>>(make_());
    held_ = true;
  });
  return *records_;
}

size_t LeafRecords::memory_bytes() const {
  return held() ? records_->size() * sizeof(PrimRecord) : 0;
}

}  // namespace rayscope
