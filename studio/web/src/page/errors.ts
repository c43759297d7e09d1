// The error replies from the engine or the arm, as the page keeps them (window.articula shows
// them: errors, lastError, errorLog, internalErrors).
export const errorReport = {
  errors: 0, // error replies so far
  lastError: "",
  errorLog: [] as string[], // the last 50 of them, oldest first
  internalErrors: [] as string[], // replies that say the engine itself went wrong (never expected)
};

/** An error reply from the engine or the arm. */
export function noteError(message: string): void {
  errorReport.errors++;
  errorReport.lastError = message;
  errorReport.errorLog.push(message);
  if (errorReport.errorLog.length > 50) errorReport.errorLog.shift();
  if (message.startsWith("internal error")) errorReport.internalErrors.push(message);
}
