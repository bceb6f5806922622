#pragma once
/// @file
/// The physical side of grasping, shared by every robot that can reach the objects (a simulated
/// device, as the Platform is): an object stands where the world put it (on the table) until a
/// hand takes it, is in one hand at most, and once put down elsewhere it is no longer there to
/// take. In a team (docs/teams.md) two robots cut off from each other may reach for one mug at
/// once: only one hand closes on it, as only one would in the real world.
#include <map>
#include <memory>
#include <string>

#include "quiver/base/result.h"

namespace quiver::agents::inline apps::agm {

class Custody {
 public:
  virtual ~Custody() = default;
  /// Closes `robot`'s hand on `object` where it stood. @returns false (and changes nothing) when
  /// another robot holds it or it was put down elsewhere; true when `robot` holds it now.
  virtual bool take(const std::string& object, const std::string& robot) = 0;
  /// `robot` lets go of `object`, wherever it is now (nothing if it did not hold it).
  virtual void put(const std::string& object, const std::string& robot) = 0;
  /// Who holds `object` ("" if nobody).
  virtual std::string holder(const std::string& object) const = 0;
};

/// Custody within one process (the simulator's robots).
class SharedCustody final : public Custody {
 public:
  bool take(const std::string& object, const std::string& robot) override;
  void put(const std::string& object, const std::string& robot) override;
  std::string holder(const std::string& object) const override;

 private:
  std::map<std::string, std::string> held_;  // object -> robot; "" once put down
};

/// Custody across processes and network namespaces of one machine: a file per object in `dir`
/// (the robots' processes share the file system), created exclusively by the hand that takes it
/// and emptied when it is put down.
class FileCustody final : public Custody {
 public:
  /// @returns kIo naming `dir` when it cannot be made.
  static Result<std::unique_ptr<FileCustody>> open(const std::string& dir);
  bool take(const std::string& object, const std::string& robot) override;
  void put(const std::string& object, const std::string& robot) override;
  std::string holder(const std::string& object) const override;

 private:
  explicit FileCustody(std::string dir) : dir_(std::move(dir)) {}
  std::string path(const std::string& object) const;
  std::string read(const std::string& object) const;
  std::string dir_;
};

}  // namespace quiver::agents::inline apps::agm
