#include "OutputFolderDialog.h"

#include <QDialogButtonBox>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPushButton>
#include <QSettings>
#include <QVBoxLayout>

namespace lodforge::studio {

namespace {

// Entries of `dir` other than . and ..; 0 when it does not exist.
qsizetype entryCount(const QString& dir) {
    return QDir(dir).entryList(QDir::AllEntries | QDir::NoDotAndDotDot | QDir::Hidden | QDir::System).size();
}

}  // namespace

OutputFolderDialog::OutputFolderDialog(const QString& title, const QString& settingsKey, const QString& initial,
                                       QWidget* parent)
    : QDialog(parent), settingsKey_(settingsKey) {
    setObjectName(QStringLiteral("outputFolderDialog"));
    setWindowTitle(title);
    auto* layout = new QVBoxLayout(this);
    layout->addWidget(new QLabel(tr("Folder (a new name creates it):"), this));
    auto* row = new QHBoxLayout;
    path_ = new QLineEdit(this);
    path_->setObjectName(QStringLiteral("folderPath"));
    path_->setMinimumWidth(420);
    path_->setText(QDir::toNativeSeparators(initial));
    auto* browse = new QPushButton(tr("Browse…"), this);
    browse->setObjectName(QStringLiteral("browseFolder"));
    connect(browse, &QPushButton::clicked, this, [this] {
        // Start from the nearest folder that exists along the typed path.
        QString start = QFileInfo(path_->text()).absoluteFilePath();
        while (!start.isEmpty() && !QFileInfo(start).isDir() && QFileInfo(start).path() != start)
            start = QFileInfo(start).path();
        const QString dir = QFileDialog::getExistingDirectory(this, windowTitle(), start);
        if (!dir.isEmpty()) path_->setText(QDir::toNativeSeparators(dir));
    });
    row->addWidget(path_, 1);
    row->addWidget(browse);
    layout->addLayout(row);
    note_ = new QLabel(this);
    note_->setObjectName(QStringLiteral("folderNote"));
    note_->setWordWrap(true);
    layout->addWidget(note_);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
    buttons->button(QDialogButtonBox::Ok)->setText(tr("Export"));
    connect(buttons, &QDialogButtonBox::accepted, this, &OutputFolderDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
    layout->addWidget(buttons);
    connect(path_, &QLineEdit::textChanged, this, &OutputFolderDialog::updateNote);
    updateNote();
}

void OutputFolderDialog::updateNote() {
    const QString dir = QFileInfo(path_->text().trimmed()).absoluteFilePath();
    if (path_->text().trimmed().isEmpty()) {
        note_->setText(tr("Type or browse to a folder."));
    } else if (!QFileInfo::exists(dir)) {
        note_->setText(tr("The folder will be created."));
    } else if (!QFileInfo(dir).isDir()) {
        note_->setText(tr("This is a file, not a folder."));
    } else if (const qsizetype n = entryCount(dir); n > 0) {
        note_->setText(tr("The folder already holds %n item(s); files of the same name will be replaced.", "", int(n)));
    } else {
        note_->setText(tr("The folder is empty."));
    }
}

void OutputFolderDialog::accept() {
    const QString typed = path_->text().trimmed();
    if (typed.isEmpty()) return updateNote();
    const QString dir = QFileInfo(QDir::fromNativeSeparators(typed)).absoluteFilePath();
    const QFileInfo info(dir);
    if (info.exists() && !info.isDir()) return note_->setText(tr("%1 is a file, not a folder.").arg(dir));
    if (!info.exists()) {
        if (!QDir().mkpath(dir)) return note_->setText(tr("Could not create the folder %1.").arg(dir));
        return finish(dir);
    }
    const qsizetype n = entryCount(dir);
    if (n == 0) return finish(dir);
    auto* box = new QMessageBox(QMessageBox::Warning, windowTitle(),
                                tr("%1 is not empty.").arg(QDir::toNativeSeparators(dir)),
                                QMessageBox::Yes | QMessageBox::No, this);
    box->setObjectName(QStringLiteral("nonEmptyFolderBox"));
    box->setInformativeText(tr("It holds %n item(s). Write into it anyway? Files of the same name are replaced.",
                               "", int(n)));
    box->button(QMessageBox::Yes)->setText(tr("Write into it"));
    box->setDefaultButton(QMessageBox::No);
    box->setAttribute(Qt::WA_DeleteOnClose);
    connect(box, &QMessageBox::finished, this, [this, box, dir](int) {
        if (box->clickedButton() == box->button(QMessageBox::Yes)) finish(dir);
    });
    box->open();
}

void OutputFolderDialog::finish(const QString& folder) {
    folder_ = folder;
    QSettings().setValue(settingsKey_, folder);
    QDialog::accept();
}

}  // namespace lodforge::studio
