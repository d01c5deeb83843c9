#pragma once
// An options struct's validate() checks its members' own with their path: a member's
// InvalidOption names the field from the enclosing struct ("run.lambda").
#include "vmas/error.hpp"

namespace vmas::internal {

template <typename MemberOptions>
void validate_member(const char* member, const MemberOptions& options) {
  try {
    options.validate();
  } catch (const InvalidOption& e) {
    throw e.within(member);
  }
}

}  // namespace vmas::internal
