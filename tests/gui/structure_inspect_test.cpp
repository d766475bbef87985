// The structure inspectors, in process under Xvfb (docs/studio.md, "Marching-cube octree priority" and
// "Octree tuning"), real pixels with tolerances:
//  - MC octree on frag_115 (a coloured RGB-D scan): the priority slider's triangle count is the tree's
//    exact count at each index and rises with it, the frame changes, the scan's colours show, and the
//    cells overlay follows the cut;
//  - out-of-core octree on Spot: knob changes rebuild (debounced, once for a burst) and the statistics
//    equal build_octree's for the same knobs; the view-dependent cut has more triangles with the camera
//    closer or a smaller screen error, stays a valid crack-free cut, draws its nodes as cells; a node
//    picked in the view is scrubbed coarser and finer.
#include "MainWindow.h"
#include "PixelStats.h"
#include "StudioSession.h"

#include "lodforge/mcoctree/mc_octree.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/octree/octree_build.h"
#include "lodforge/octree/octree_store.h"
#include "lodforge/pack/preset.h"
#include "lodforge/widgets/LevelViews.h"
#include "lodforge/widgets/LoadJob.h"
#include "lodforge/widgets/McoPriorityPanel.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/OctreeTuningPanel.h"
#include "lodforge/widgets/ParametersPanel.h"
#include "lodforge/widgets/ViewOptions.h"
#include "lodforge/widgets/VtkView.h"

#include <QApplication>
#include <QFile>
#include <QLabel>
#include <QLocale>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSlider>
#include <QSpinBox>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QUndoStack>

#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <tuple>

using lodforge::studio::MainWindow;
using lodforge::testing::differingFraction;
using lodforge::testing::freshFrame;
using lodforge::testing::measure;
using lodforge::testing::nearColor;
using lodforge::widgets::McoPriorityPanel;
using lodforge::widgets::OctreeTuningPanel;
using lodforge::widgets::viewBackgroundColor;
using lodforge::widgets::VtkView;

namespace {

const QString fragPath = QStringLiteral(LODFORGE_SHARED_DATA "/color-open3d-frag115/frag_115.ply");
const QString spotPath = QStringLiteral(LODFORGE_SAMPLES_DIR "/spot/spot_triangulated.obj");

// Pixels that differ between two frames of the same camera (any channel by more than 24).
qint64 changedPixels(const QImage& a, const QImage& b) {
    qint64 n = 0;
    for (int y = 0; y < a.height(); ++y) {
        const auto* la = reinterpret_cast<const QRgb*>(a.constScanLine(y));
        const auto* lb = reinterpret_cast<const QRgb*>(b.constScanLine(y));
        for (int x = 0; x < a.width(); ++x)
            if (!nearColor(lb[x], QColor::fromRgb(la[x]), 24)) ++n;
    }
    return n;
}

// Edges used by exactly one triangle, vertices welded by position (UV seams split Spot's wedges).
std::size_t borderEdges(const lodforge::Mesh& mesh) {
    std::map<std::tuple<float, float, float>, std::uint32_t> ids;
    std::vector<std::uint32_t> id(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const auto& p = mesh.positions[v];
        id[v] = ids.emplace(std::make_tuple(p.x, p.y, p.z), std::uint32_t(ids.size())).first->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = id[mesh.indices[t + k]], b = id[mesh.indices[t + (k + 1) % 3]];
            if (a == b) continue;
            if (a > b) std::swap(a, b);
            ++uses[{a, b}];
        }
    return std::size_t(std::count_if(uses.begin(), uses.end(), [](const auto& e) { return e.second == 1; }));
}

}  // namespace

class StructureInspectTest : public QObject {
    Q_OBJECT

private slots:
    void initTestCase();
    void init();
    void cleanup();

    void mcoPrioritySliderExtractsColouredLevels();
    void mcoOfALowPolyMeshSaysItsFacesWereSampled();
    void octreeKnobsUpdateStatistics();
    void octreeViewDependentCutAndNodeScrub();

private:
    bool buildOctree(int maxTriangles, int maxDepth);
    void setCells(bool on) {
        lodforge::widgets::ViewOptions o = window_->viewOptions();
        o.cells = on;
        window_->setViewOptions(o);
    }
    std::unique_ptr<MainWindow> window_;
};

void StructureInspectTest::initTestCase() {
    QVERIFY2(QFile::exists(fragPath), qPrintable(fragPath));
    QVERIFY2(QFile::exists(spotPath), qPrintable(spotPath));
    QSettings().clear();
}

void StructureInspectTest::init() {
    window_ = lodforge::testing::openStudioWindow();
    QVERIFY(window_);
}

void StructureInspectTest::cleanup() {
    while (QWidget* modal = QApplication::activeModalWidget()) modal->close();
    window_.reset();
}

// Spot (2,930 vertices, faces longer than two cubes at 96): the dock says how many points the build added
// on them (no density warning), and draws the surface.
void StructureInspectTest::mcoOfALowPolyMeshSaysItsFacesWereSampled() {
    QVERIFY(lodforge::testing::loadInStudio(*window_, spotPath));
    lodforge::Preset preset = window_->preset();
    preset.mcoctree.resolution = 96;
    window_->setPreset(preset);
    McoPriorityPanel* panel = window_->mcoPriorityPanel();
    QSignalSpy built(panel, &McoPriorityPanel::built);
    QTest::mouseClick(panel->buildButton(), Qt::LeftButton);
    QVERIFY(built.wait(60000));
    QVERIFY2(built.at(0).at(0).toBool(), qPrintable(built.at(0).at(1).toString()));
    const QString status = panel->findChild<QLabel*>(QStringLiteral("mcoStatus"))->text();
    QVERIFY2(status.contains(QStringLiteral("points added on the")), qPrintable(status));
    QVERIFY2(!status.contains(QStringLiteral("exceeds the data density")), qPrintable(status));
    QVERIFY(lodforge::testing::mcoSettled(panel));
    const QImage frame = freshFrame(window_->view());
    QVERIFY(measure(frame, viewBackgroundColor(), frame.rect()).modelFraction() > 0.05);
}

void StructureInspectTest::mcoPrioritySliderExtractsColouredLevels() {
    QVERIFY(lodforge::testing::loadInStudio(*window_, fragPath));
    lodforge::Preset preset = window_->preset();
    preset.mcoctree.resolution = 64;
    window_->setPreset(preset);
    McoPriorityPanel* panel = window_->mcoPriorityPanel();
    QVERIFY(panel->buildButton()->text().contains(QStringLiteral("64")));
    QSignalSpy built(panel, &McoPriorityPanel::built);
    // Cancel drops a build: no result, no tree.
    panel->build();
    QVERIFY(panel->isBuilding());
    panel->cancel();
    QVERIFY(!panel->isBuilding());
    QTest::qWait(300);
    QVERIFY(built.isEmpty() && !panel->hasTree());
    QTest::mouseClick(panel->buildButton(), Qt::LeftButton);
    QVERIFY(built.wait(60000));
    QVERIFY2(built.at(0).at(0).toBool(), qPrintable(built.at(0).at(1).toString()));
    const lodforge::McOctree* tree = panel->tree();
    QVERIFY(tree && tree->has_colors() && tree->max_priority() > 100);
    QCOMPARE(std::size_t(panel->slider()->maximum()), tree->max_priority());

    // The slider (through its signal) at ten indices: the label's count is the tree's exact count.
    VtkView* view = window_->view();
    auto* levelLabel = window_->levelViews()->singleLabel();
    std::uint64_t previous = 0;
    const std::size_t top = tree->max_priority();
    for (int i = 1; i <= 10; ++i) {
        const std::size_t p = top * std::size_t(i * i) / 100;  // denser at the coarse end
        panel->slider()->setValue(int(p));
        const QString expected = QLocale().toString(qulonglong(lodforge::mc_triangles_at(*tree, p)));
        QVERIFY(lodforge::testing::mcoSettled(panel));
        QVERIFY(panel->label()->text().contains(expected + QStringLiteral(" triangles")));
        QCOMPARE(panel->priority(), p);
        QCOMPARE(panel->triangles(), lodforge::mc_triangles_at(*tree, p));
        QCOMPARE(levelLabel->text(), panel->labelText());
        QVERIFY2(panel->triangles() >= previous, qPrintable(panel->labelText()));
        previous = panel->triangles();
    }
    qInfo("MC octree: %zu priorities, last update %.1f ms (%s), %s", top, panel->lastExtractMs(),
          qPrintable(panel->timing()), qPrintable(panel->labelText()));

    // The triangle budget box: the finest index within the budget.
    panel->budgetBox()->setValue(20000);
    QVERIFY(lodforge::testing::mcoSettled(panel));
    QVERIFY(panel->triangles() <= 20000 && panel->priority() < top);
    QVERIFY(lodforge::mc_triangles_at(*tree, panel->priority() + 1) > 20000);

    // Coarse and fine frames differ; the scan's colours show.
    panel->setPriority(top / 50);
    QVERIFY(lodforge::testing::mcoSettled(panel));
    const std::uint64_t coarseTriangles = panel->triangles();
    const QImage coarse = freshFrame(view);
    panel->setPriority(top);
    QVERIFY(lodforge::testing::mcoSettled(panel));
    QVERIFY(panel->triangles() > 2 * coarseTriangles);
    const QImage fine = freshFrame(view);
    const double differ = differingFraction(coarse, fine, viewBackgroundColor());
    const auto stats = measure(fine, viewBackgroundColor(), fine.rect());
    qInfo("coarse %llu / fine %llu triangles: %.3f of the model pixels differ; chromatic %.3f, %d colours",
          qulonglong(coarseTriangles), qulonglong(panel->triangles()), differ, stats.chromaticFraction,
          stats.distinctColors);
    QVERIFY(differ > 0.05);
    QVERIFY(stats.modelFraction() > 0.05);
    // The scan's colours against the same frame without vertex colours (grey shading: no chromatic pixel).
    lodforge::widgets::ViewOptions grey = window_->viewOptions();
    grey.vertexColors = false;
    window_->setViewOptions(grey);
    const QImage greyFrame = freshFrame(view);
    grey.vertexColors = true;
    window_->setViewOptions(grey);
    const auto greyStats = measure(greyFrame, viewBackgroundColor(), greyFrame.rect());
    const double colourDiffer = differingFraction(greyFrame, fine, viewBackgroundColor());
    qInfo("without colours: chromatic %.4f, %d colours; %.3f of the pixels differ", greyStats.chromaticFraction,
          greyStats.distinctColors, colourDiffer);
    QVERIFY2(stats.chromaticFraction > 0.01 && stats.chromaticFraction > 10 * greyStats.chromaticFraction &&
                 stats.distinctColors > 2 * greyStats.distinctColors && colourDiffer > 0.2,
             "the scan's colours are not shown");

    // The cells overlay is the cut at the slider's index: more cells, and more line pixels, when finer.
    setCells(true);
    QVERIFY(lodforge::testing::mcoSettled(panel));
    const QImage fineCells = freshFrame(view);
    const std::size_t fineCellCount = panel->cutCells();
    QCOMPARE(lodforge::widgets::describe(*view->overlayScene()).lines, 12 * fineCellCount);
    panel->setPriority(top / 50);
    QVERIFY(lodforge::testing::mcoSettled(panel));
    const QImage coarseCells = freshFrame(view);
    const std::size_t coarseCellCount = panel->cutCells();
    QCOMPARE(lodforge::widgets::describe(*view->overlayScene()).lines, 12 * coarseCellCount);
    const qint64 fineLines = changedPixels(fine, fineCells), coarseLines = changedPixels(coarse, coarseCells);
    qInfo("cells: %zu coarse (%lld line pixels), %zu fine (%lld)", coarseCellCount, qlonglong(coarseLines),
          fineCellCount, qlonglong(fineLines));
    QVERIFY(coarseCellCount > 0 && fineCellCount > 2 * coarseCellCount);
    QVERIFY(coarseLines > 100 && fineLines > coarseLines);

    // Choosing a stored level leaves the inspection.
    window_->levelViews()->setCurrentLevel(0);
    QVERIFY(window_->levelViews()->inspectionOwner() == nullptr);
    QVERIFY(levelLabel->text().startsWith(QStringLiteral("Original")));
}

bool StructureInspectTest::buildOctree(int maxTriangles, int maxDepth) {
    lodforge::Preset preset = window_->preset();
    preset.octree.max_triangles_per_node = std::uint32_t(maxTriangles);
    preset.octree.max_depth = std::uint32_t(maxDepth);
    window_->setPreset(preset);
    OctreeTuningPanel* panel = window_->octreeTuningPanel();
    QSignalSpy built(panel, &OctreeTuningPanel::built);
    panel->build();
    return built.wait(60000) && built.at(0).at(0).toBool();
}

void StructureInspectTest::octreeKnobsUpdateStatistics() {
    QVERIFY(lodforge::testing::loadInStudio(*window_, spotPath));
    OctreeTuningPanel* panel = window_->octreeTuningPanel();
    QVERIFY(buildOctree(300, 8));

    // The reference: build_octree with the same knobs on the same mesh (written as PLY, as the panel does).
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const std::string ply = QFile::encodeName(dir.filePath(QStringLiteral("spot.ply"))).toStdString();
    lodforge::write_mesh(window_->model()->mesh, ply);
    auto reference = [&](int maxTriangles, int maxDepth) {
        lodforge::OctreeBuildParams p;
        p.max_triangles = std::size_t(maxTriangles);
        p.max_depth = maxDepth;
        p.memory_bytes = std::size_t{window_->preset().octree.memory_mb} << 20;
        p.weights = window_->preset().weights;
        const std::string asset = QFile::encodeName(dir.filePath(QStringLiteral("ref.lfoct"))).toStdString();
        lodforge::build_octree(ply, asset, p);
        return lodforge::OctreeStore(asset).stats();
    };
    auto checkAgainst = [&](const lodforge::OctreeStats& r) {
        const lodforge::OctreeStats& s = panel->stats();
        QCOMPARE(s.nodes, r.nodes);
        QCOMPARE(s.leaves, r.leaves);
        QCOMPARE(s.depth_reached, r.depth_reached);
        QVERIFY(s.triangles_per_level == r.triangles_per_level);
        const QLocale locale;
        const QString text = panel->statsLabel()->text();
        QVERIFY2(text.contains(locale.toString(qulonglong(r.nodes)) + QStringLiteral(" nodes")) &&
                     text.contains(locale.toString(qulonglong(r.leaves)) + QStringLiteral(" leaves")) &&
                     text.contains(QStringLiteral("depth %1 reached").arg(r.depth_reached)),
                 qPrintable(text));
        QTableWidget* table = panel->levelTable();
        QCOMPARE(std::size_t(table->rowCount()), r.triangles_per_level.size());
        for (int l = 0; l < table->rowCount(); ++l)
            QCOMPARE(table->item(l, 1)->data(Qt::UserRole).toULongLong(), r.triangles_per_level[std::size_t(l)]);
    };
    const lodforge::OctreeStats first = reference(300, 8);
    checkAgainst(first);
    qInfo("300 per leaf: %s", qPrintable(panel->statsLabel()->text()));

    // The tree's cells over the original: one box per node, drawn when the overlay is on.
    VtkView* view = window_->view();
    QVERIFY(window_->levelViews()->inspectionOwner() == panel);
    QCOMPARE(lodforge::widgets::describe(*view->overlayScene()).lines, 12 * first.nodes);
    const QImage plain = freshFrame(view);
    setCells(true);
    const QImage firstCells = freshFrame(view);
    QVERIFY(changedPixels(plain, firstCells) > 500);

    // A burst of knob changes in the Parameters panel's spin boxes: one rebuild, with the last values.
    QSignalSpy built(panel, &OctreeTuningPanel::built);
    auto* maxTriangles = window_->parametersPanel()->findChild<QSpinBox*>(QStringLiteral("maxTrianglesPerNode"));
    auto* maxDepth = window_->parametersPanel()->findChild<QSpinBox*>(QStringLiteral("maxDepth"));
    QVERIFY(maxTriangles && maxDepth);
    maxTriangles->setValue(150);
    QVERIFY(panel->rebuildPending());
    maxTriangles->setValue(60);
    maxDepth->setValue(3);
    QVERIFY(built.wait(60000));
    QVERIFY2(built.at(0).at(0).toBool(), qPrintable(built.at(0).at(1).toString()));
    QTest::qWait(OctreeTuningPanel::debounceMs + 200);
    QCOMPARE(built.count(), 1);
    QCOMPARE(panel->builtParams().max_triangles, std::size_t(60));
    QCOMPARE(panel->builtParams().max_depth, 3);
    const lodforge::OctreeStats second = reference(60, 3);
    checkAgainst(second);
    QVERIFY(second.depth_reached <= 3 && second.nodes != first.nodes);
    QCOMPARE(lodforge::widgets::describe(*view->overlayScene()).lines, 12 * second.nodes);
    QVERIFY(changedPixels(firstCells, freshFrame(view)) > 200);  // the cells of the new tree
    qInfo("60 per leaf, depth 3: %s", qPrintable(panel->statsLabel()->text()));

    // Undo (max depth back to 8) schedules a rebuild too; Cancel stops it before it starts.
    window_->undoStack()->undo();
    QVERIFY(panel->rebuildPending());
    panel->cancel();
    QVERIFY(!panel->rebuildPending() && !panel->isBuilding());
    QTest::qWait(OctreeTuningPanel::debounceMs + 200);
    QCOMPARE(built.count(), 1);
    checkAgainst(second);  // the asset shown is still the last one built
}

void StructureInspectTest::octreeViewDependentCutAndNodeScrub() {
    QVERIFY(lodforge::testing::loadInStudio(*window_, spotPath));
    OctreeTuningPanel* panel = window_->octreeTuningPanel();
    QVERIFY(buildOctree(200, 8));
    lodforge::OctreeStore& store = *panel->store();
    const std::size_t inputBorders = borderEdges(window_->model()->mesh);
    QCOMPARE(inputBorders, std::size_t(0));

    VtkView* view = window_->view();
    window_->levelViews()->resetView();
    panel->setFrustumCulling(false);  // every node in the cut: only the distance decides
    panel->setScreenError(2);
    panel->setViewDependent(true);
    QVERIFY(lodforge::testing::cutSettled(panel));
    QVERIFY(window_->levelViews()->inspectionOwner() == panel);
    const std::uint64_t atReset = panel->cutTriangles();
    QVERIFY(lodforge::is_valid_cut(store, panel->cut()));
    QCOMPARE(borderEdges(panel->cutMesh()), inputBorders);
    QVERIFY(window_->levelViews()->singleLabel()->text().contains(
        QLocale().toString(qulonglong(atReset)) + QStringLiteral(" triangles")));

    // The camera closer (through the view's camera signal): a finer cut; farther: a coarser one.
    VtkView::ViewCamera camera = view->viewCamera();
    auto moved = [&](double factor) {
        VtkView::ViewCamera c = camera;
        for (int k = 0; k < 3; ++k) c.position[k] = c.focalPoint[k] + (camera.position[k] - c.focalPoint[k]) * factor;
        QSignalSpy updated(panel, &OctreeTuningPanel::cutUpdated);
        view->setViewCamera(c);
        if (!updated.wait(5000)) return std::uint64_t(0);
        return panel->cutTriangles();
    };
    const std::uint64_t closer = moved(0.3), farther = moved(4.0);
    qInfo("view-dependent cut at 2 px: %llu triangles at reset, %llu closer, %llu farther", qulonglong(atReset),
          qulonglong(closer), qulonglong(farther));
    QVERIFY(closer > atReset && atReset > farther && farther > 0);
    QVERIFY(lodforge::is_valid_cut(store, panel->cut()));
    QCOMPARE(borderEdges(panel->cutMesh()), inputBorders);

    // The screen error slider: more pixels allowed, fewer triangles.
    view->setViewCamera(camera);
    QTRY_COMPARE_WITH_TIMEOUT(panel->cutTriangles(), atReset, 5000);
    panel->screenErrorSlider()->setValue(40);  // 20 px, through the slider's signal
    QTRY_VERIFY_WITH_TIMEOUT(panel->cutTriangles() < atReset, 5000);
    panel->setScreenError(2);
    QVERIFY(lodforge::testing::cutSettled(panel));
    QCOMPARE(panel->cutTriangles(), atReset);

    // The cut's nodes as cells, one box each, coloured by level: the frame changes where they are drawn.
    const QImage plain = freshFrame(view);
    setCells(true);
    const QImage cells = freshFrame(view);
    QCOMPARE(lodforge::widgets::describe(*view->overlayScene()).lines, 12 * panel->cut().size());
    QVERIFY(changedPixels(plain, cells) > 500);
    setCells(false);

    // Pick the node under the view's centre with a click, then scrub it: coarser lowers the count (the
    // pinned node's subtree replaced by its simplified mesh), finer raises it; always a valid cut.
    const QPoint centre(view->width() / 2, view->height() / 2);
    auto* pick = panel->findChild<QPushButton*>(QStringLiteral("octreePickNode"));
    QVERIFY(pick && pick->isEnabled());
    pick->setChecked(true);
    QTest::mouseClick(view, Qt::LeftButton, {}, centre);
    QVERIFY2(panel->pinnedNode().has_value(), "no node picked at the view's centre");
    QVERIFY(lodforge::testing::cutSettled(panel));
    const std::uint32_t picked = *panel->pinnedNode();
    const std::uint64_t beforeScrub = panel->cutTriangles();
    QCOMPARE(beforeScrub, atReset);  // pinning at its own level changes nothing
    const QImage beforeFrame = freshFrame(view);
    std::uint64_t coarsest = beforeScrub;
    window_->activateWindow();
    view->setFocus();
    QVERIFY(QTest::qWaitForWindowActive(window_.get()));
    for (int i = 0; i < 3; ++i) {
        QTest::keyClick(view, Qt::Key_BracketRight);  // the Coarser shortcut
        QVERIFY(lodforge::testing::cutSettled(panel));
        coarsest = panel->cutTriangles();
        QVERIFY(lodforge::is_valid_cut(store, panel->cut()));
        QCOMPARE(borderEdges(panel->cutMesh()), inputBorders);
    }
    qInfo("node %u scrubbed coarser: %llu -> %llu triangles (now node %u level %d)", picked,
          qulonglong(beforeScrub), qulonglong(coarsest), *panel->pinnedNode(), panel->pinnedLevel());
    QVERIFY(coarsest < beforeScrub);
    QVERIFY(window_->levelViews()->singleLabel()->text().contains(QStringLiteral("level %1").arg(panel->pinnedLevel())));
    QVERIFY(differingFraction(beforeFrame, freshFrame(view), viewBackgroundColor()) > 0.005);
    QTest::keyClick(view, Qt::Key_BracketLeft);  // the Finer shortcut
    QVERIFY(lodforge::testing::cutSettled(panel));
    QVERIFY(panel->cutTriangles() > coarsest);
    while (panel->pinnedLevel() > 0) panel->finer();
    QVERIFY(lodforge::testing::cutSettled(panel));
    QVERIFY(panel->cutTriangles() > beforeScrub);
    QVERIFY(lodforge::is_valid_cut(store, panel->cut()));
    QCOMPARE(borderEdges(panel->cutMesh()), inputBorders);

    // A smaller view is a smaller viewport: the cut follows the resize, with fewer triangles. Unpinned
    // first: a pin holds its node's part of the cut whatever the view (the root pinned at its input
    // triangles holds all of it).
    panel->unpin();
    QVERIFY(lodforge::testing::cutSettled(panel));
    {
        const std::uint64_t large = panel->cutTriangles();
        QSignalSpy updated(panel, &OctreeTuningPanel::cutUpdated);
        window_->resize(800, 560);
        QVERIFY(updated.wait(5000));
        QVERIFY(lodforge::testing::cutSettled(panel));
        qInfo("resized view: %llu -> %llu triangles", qulonglong(large), qulonglong(panel->cutTriangles()));
        QVERIFY(panel->cutTriangles() < large);
        QVERIFY(lodforge::is_valid_cut(store, panel->cut()));
    }

    // Off: the tree's cells again; without them the stored level comes back.
    panel->setViewDependent(false);
    QVERIFY(window_->levelViews()->inspectionOwner() == panel);
    QVERIFY(window_->levelViews()->singleLabel()->text().contains(QStringLiteral("the tree's cells")));
    panel->setShowTree(false);
    QVERIFY(window_->levelViews()->inspectionOwner() == nullptr);
    QVERIFY(window_->levelViews()->singleLabel()->text().startsWith(QStringLiteral("Original")));
}

QTEST_MAIN(StructureInspectTest)
#include "structure_inspect_test.moc"
