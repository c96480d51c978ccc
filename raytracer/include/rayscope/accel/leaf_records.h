// The bounded primitives as whole records (PrimRecord) in the structure's
// leaf order: what the tools read (range queries, teaching views, the binary
// tree built again, walks an observer watches). Every structure but the BVH
// tests them in its walk and keeps them. The BVH's triangle blocks hold the
// same vertices, bit for bit, so a render needs only each record's id; its
// records are dropped after the build and made again from the blocks the
// first time a tool asks (as bvh_on_demand.h does for the binary tree).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "rayscope/accel/prim_record.h"

namespace rayscope {

class LeafRecords {
 public:
  /// Makes the records again when they are asked for after being dropped.
  using Make = std::function<std::vector<PrimRecord>()>;

  /// No records.
  LeafRecords() : LeafRecords(std::vector<PrimRecord>{}) {}
  /// Records held from the start.
  explicit LeafRecords(std::vector<PrimRecord> held);
  /// Records made by `make` on the first get().
  explicit LeafRecords(Make make) : make_(std::move(make)) {}
  /// `other`'s records, shared while it holds them, else made by `make`.
  LeafRecords(const LeafRecords& other, Make make);
  LeafRecords(const LeafRecords&) = delete;
  LeafRecords& operator=(const LeafRecords&) = delete;

  /// The records: held, or made on the first call (once, whichever thread
  /// asks first).
  const std::vector<PrimRecord>& get() const { return held() ? *records_ : make(); }
  /// Whether they are held now (memory_bytes() counts them).
  bool held() const { return held_.load(std::memory_order_acquire); }
  /// Bytes of the records held now.
  size_t memory_bytes() const;

 private:
  /// get() when not held yet.
  const std::vector<PrimRecord>& make() const;

  mutable std::once_flag once_;
  mutable std::shared_ptr<const std::vector<PrimRecord>> records_;
  mutable std::atomic<bool> held_{false};
  Make make_;
};

}  // namespace rayscope
