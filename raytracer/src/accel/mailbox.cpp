#include "rayscope/accel/mailbox.h"

#include <algorithm>
#include <vector>

namespace rayscope {

namespace {
/// The calling thread's stamps and the stamp of its latest query.
struct Mailbox {
  uint32_t query = 0;
  std::vector<uint32_t> stamps;
};
}  // namespace

MailboxQuery::MailboxQuery(uint32_t num_prims) {
  thread_local Mailbox mailbox;
  if (mailbox.stamps.size() < num_prims) mailbox.stamps.resize(num_prims, 0u);
  if (++mailbox.query == 0) {  // wrapped around: old stamps could match again
    std::fill(mailbox.stamps.begin(), mailbox.stamps.end(), 0u);
    mailbox.query = 1;
  }
  stamp_ = mailbox.query;
  stamps_ = mailbox.stamps.data();
}

}  // namespace rayscope
