// Loading a mesh file off the GUI thread: read, summarise, decode textures, build the drawable scene.
#pragma once

#include "lodforge/io/image_decode.h"
#include "lodforge/mesh.h"
#include "lodforge/io/mesh_info.h"
#include "lodforge/progress.h"

#include <QFutureWatcher>
#include <QObject>
#include <QString>
#include <QStringList>

#include <memory>

namespace lodforge::widgets {

class MeshScene;
class QueuedProgress;

// Everything the studio shows about one loaded file.
struct LoadedModel {
    QString path;
    lodforge::Mesh mesh;
    lodforge::MeshInfo info;
    QStringList warnings;  // problems that did not stop the load, e.g. a texture that does not decode
    std::shared_ptr<const MeshScene> scene;
    // The decoded base colour texture of each material (null where none), for the scenes of its levels.
    std::vector<std::shared_ptr<const lodforge::Image>> images;
    qint64 elapsedMs = 0;  // wall time of the whole load
};

struct LoadResult {
    enum class Status { ok, failed, cancelled };
    Status status = Status::failed;
    QString path;
    QString error;  // for failed: the problem, as reported by the reader (it names the file)
    std::shared_ptr<const LoadedModel> model;  // for ok
};

// One load of one file. start() runs the work on Qt's thread pool; progressChanged and finished are
// emitted on the thread that owns the job (the GUI thread). Every exception of the work is caught on the
// worker and comes back as a failed result: none crosses the thread boundary. Destroying a running job
// cancels it and waits for the worker.
class LoadJob : public QObject {
    Q_OBJECT

public:
    explicit LoadJob(QString path, QObject* parent = nullptr);
    ~LoadJob() override;

    void start();
    // Asks the worker to stop at its next progress check; finished() then reports Status::cancelled.
    void cancel();
    bool isRunning() const;
    const QString& path() const { return path_; }

    // The work itself, synchronous; used by start() on the worker and usable directly (tests, tools).
    // Never throws.
    static LoadResult load(const QString& path, lodforge::Progress* progress = nullptr);

signals:
    void progressChanged(double fraction, const QString& stage);
    void finished(const lodforge::widgets::LoadResult& result);

private:
    QString path_;
    std::unique_ptr<QueuedProgress> progress_;
    QFutureWatcher<LoadResult> watcher_;
};

}  // namespace lodforge::widgets
