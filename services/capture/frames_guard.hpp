#pragma once
/// One capture per namespace: finds other writers of our frames topic through the built-in
/// DCPSPublication topic and names them by the identity their capture put in its participant's
/// user data ("df_capture host=<host> pid=<pid>").
#include <dds/dds.h>

#include <set>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "dds/entity.hpp"

namespace df::capture {

/// "df_capture host=<hostname> pid=<pid>" of this process.
std::string own_identity();

/// True when `identity` (own_identity() of some capture) names a process of this host that no
/// longer exists: a capture killed moments ago, whose writer discovery still lists.
bool is_dead_local_capture(const std::string& identity);

class FramesGuard {
  public:
    /// Puts own_identity() into the participant's user data and opens the built-in readers.
    /// frames_writer: our writer of `topic`.
    static Result<FramesGuard> create(dds_entity_t participant, dds_entity_t frames_writer,
                                      std::string topic);
    /// Descriptions of the other writers of the topic now ("df_capture host=h pid=p", or the
    /// participant's GUID when it has no such user data).
    std::vector<std::string> other_writers();
    /// other_writers() reported once each: logs an error line for each writer not seen before,
    /// returns whether there is any now.
    bool check_and_report();

  private:
    FramesGuard(dds::Entity publications, dds::Entity participants, dds_guid_t own,
                std::string topic)
        : publications_(std::move(publications)),
          participants_(std::move(participants)),
          own_(own),
          topic_(std::move(topic)) {}
    std::string describe_participant(const dds_guid_t& key);

    dds::Entity publications_;
    dds::Entity participants_;
    dds_guid_t own_;
    std::string topic_;
    std::set<std::string> reported_;
    std::set<std::string> dead_;  // dead local captures already logged
};

}  // namespace df::capture
