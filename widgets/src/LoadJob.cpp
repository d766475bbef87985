#include "lodforge/widgets/LoadJob.h"

#include "lodforge/error.h"
#include "lodforge/io/image_decode.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/render/surface.h"
#include "lodforge/widgets/Job.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/QueuedProgress.h"

#include <QFile>
#include <QtConcurrent/QtConcurrentRun>

#include <string>

namespace lodforge::widgets {

LoadJob::LoadJob(QString path, QObject* parent) : QObject(parent), path_(std::move(path)) {
    progress_ = std::make_unique<QueuedProgress>(this, [this](double fraction, const QString& stage) {
        emit progressChanged(fraction, stage);
    });
    connect(&watcher_, &QFutureWatcher<LoadResult>::finished, this, [this] {
        // The future holds exactly one result: load() never throws.
        emit finished(watcher_.result());
    });
}

LoadJob::~LoadJob() {
    // The worker reports to this object: it must be done before the object goes.
    progress_->cancel();
    watcher_.waitForFinished();
}

void LoadJob::start() {
    if (watcher_.isRunning()) return;
    QueuedProgress* progress = progress_.get();
    watcher_.setFuture(QtConcurrent::run([path = path_, progress] { return load(path, progress); }));
}

void LoadJob::cancel() { progress_->cancel(); }

bool LoadJob::isRunning() const { return watcher_.isRunning(); }

LoadResult LoadJob::load(const QString& path, Progress* progress) {
    LoadResult result;
    result.path = path;
    auto model = std::make_shared<LoadedModel>();
    // Job::run catches everything the reader throws; its messages start with the path.
    const JobResult run = Job::run(path, [&](Progress* p) {
        model->path = path;
        const std::string file = QFile::encodeName(path).toStdString();
        ReadOptions read;
        read.place_every_instance = true;  // a viewer shows every placement of an instanced glTF mesh
        model->mesh = read_mesh(file, read, p);
        std::vector<std::string> warnings;
        model->images = render::decodeBaseColorTextures(model->mesh, &warnings, p);
        for (const std::string& w : warnings) model->warnings << QString::fromStdString(w);
        check_progress(p, 0.0, "Summarising");
        model->info = mesh_info(model->mesh, file, format_name(detect_format(file)));
        check_progress(p, 0.0, "Preparing the view");
        model->scene = buildMeshScene(model->mesh, model->images);
        check_progress(p, 1.0, "Preparing the view");
    }, progress);
    model->elapsedMs = run.elapsedMs;
    switch (run.status) {
    case JobResult::Status::ok:
        result.status = LoadResult::Status::ok;
        result.model = std::move(model);
        break;
    case JobResult::Status::cancelled: result.status = LoadResult::Status::cancelled; break;
    case JobResult::Status::failed: result.status = LoadResult::Status::failed; break;
    }
    result.error = run.error;
    return result;
}

}  // namespace lodforge::widgets
