// Mailboxing (lecture: "store multiple times"): a structure that stores a
// primitive in several cells tests it at most once per query all the same.
//
// Exact, not a cache: every thread keeps a stamp per primitive (thread_local,
// grown to the largest structure it walked, never shrunk: 4 bytes per
// primitive per thread) and every query takes a new stamp value; a primitive
// is tested when its stamp differs and then takes the query's. No allocation
// per query, no locks. Queries on one thread must not nest (a primitive test
// never starts another query), and a structure holds at most 2^32 - 1
// primitives.
#pragma once

#include <cstdint>

namespace rayscope {

/// One query's view of the calling thread's mailbox.
class MailboxQuery {
 public:
  /// Starts a query over primitives 0 .. num_prims - 1.
  explicit MailboxQuery(uint32_t num_prims);
  /// True the first time `prim` is seen in this query, false after.
  bool first_visit(uint32_t prim) {
    if (stamps_[prim] == stamp_) return false;
    stamps_[prim] = stamp_;
    return true;
  }

 private:
  uint32_t* stamps_;
  uint32_t stamp_;
};

}  // namespace rayscope
